// Write-then-rename, so that no half-written file ever looks complete.
#pragma once

#include <string>

namespace lista::io {

// Writes `content` to "<path>.tmp.<pid>" and renames it to `path`.
void write_file_atomic(const std::string& path, const std::string& content);

// Commits a temp file to its final name (throws lista::Error on failure).
void commit_file(const std::string& temp_path, const std::string& final_path);

// Removes the temp files and folders in `dir` ("<name>.tmp.<pid>") that a
// process left when it was killed while writing (SIGKILL, power loss): those
// whose process no longer runs. A live one (a second run writing into the
// same folder) stays. Returns how many went.
size_t remove_dead_temps(const std::string& dir);

}  // namespace lista::io

namespace lista::io {
// The temp name write_file_atomic uses for `path` ("<path>.tmp.<pid>").
std::string temp_name(const std::string& path);
}  // namespace lista::io
