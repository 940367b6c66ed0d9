// rosbag2's metadata.yaml: the few keys a reader needs, parsed line by line
// (no YAML library), and a writer of the whole file (version 5).
#pragma once

#include "storage.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace lista::bag::ros2 {

struct BagMetadata {
  std::string storage_identifier;          // "sqlite3" or "mcap"
  std::vector<std::string> relative_file_paths;
  std::string compression_format, compression_mode;
};

// Parses `text` read from `file` (named in errors, with the line). Checks
// what a reader needs: a known storage, at least one file, no compression.
BagMetadata parse_metadata(const std::string& text, const std::string& file);

struct TopicCount {
  std::string name, type;
  uint64_t messages = 0;
};

std::string format_metadata(const std::string& storage_identifier, const std::string& relative_file,
                            const std::vector<TopicCount>& topics, int64_t start_ns, int64_t end_ns);

}  // namespace lista::bag::ros2
