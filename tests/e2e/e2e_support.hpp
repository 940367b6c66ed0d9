// Helpers for the end-to-end suites: run a program, read its output, and a
// temporary folder removed when the test ends.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace e2e {

struct Result {
  int status = -1;     // exit code
  std::string output;  // stdout (stderr goes to a file next to it, appended on failure)
};

// Runs `command` through the shell; stdout captured.
Result run(const std::string& command);

std::string bin(const std::string& program);  // path of a built program
// Runs `lista-sim ARGS --threads 2 --out OUT` (stderr captured too): the
// datasets the suites generate.
Result simulate(const std::string& args, const std::filesystem::path& out);
std::string source(const std::string& path);  // path inside the source tree
std::string read_file(const std::filesystem::path& p);

// The Python 3 interpreter CMake found for the analysis scripts under bench/
// (plain Python, no packages); empty when none was found.
std::string python3();

// The body rows of every Markdown table in `text` ("| a | b |" lines that
// are neither a header nor a "|---|" rule), each as its trimmed cells.
std::vector<std::vector<std::string>> markdown_rows(const std::string& text);

class TempDir {
 public:
  explicit TempDir(const std::string& tag);
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace e2e
