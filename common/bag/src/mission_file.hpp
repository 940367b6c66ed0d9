// Internal: a bag mission's mission.toml (the BagOptions keys and
// scan_spacing), each key optional.
#pragma once

#include <lista_bag/bag_mission.hpp>

#include <optional>

namespace lista::bag {

struct MissionFile {
  BagOptions options;  // the defaults, with the file's keys over them
  std::optional<double> scan_spacing;
};

// Reads `path` when it exists; unknown keys, wrong types and values out of
// range are errors with the file and line.
MissionFile read_mission_file(const std::string& path, const BagOptions& defaults);

}  // namespace lista::bag
