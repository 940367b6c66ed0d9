// Reading a dataset of missions (data contract, sect. 1).
#pragma once

#include <lista/missions.hpp>

#include <string>
#include <vector>

namespace lista::io {

struct DatasetOptions {
  std::vector<std::string> missions;  // names to read, in this order; empty = all, sorted
  bool load_points = true;            // false: poses and file lists only
  int threads = 1;
};

// The mission folders of a dataset (sorted names), or the dataset itself when
// it is a single VIEWPOINT-layout folder. Throws lista::Error if none.
std::vector<std::string> list_missions(const std::string& dataset_dir);

// Reads one mission folder: poses.txt + scans/ (or the VIEWPOINT layout),
// poses_gt.txt when present. Errors: scan count != pose count, unreadable or
// malformed file, non-orthonormal rotation, empty mission.
Mission read_mission(const std::string& mission_dir, const DatasetOptions& options = {});

MissionSet read_dataset(const std::string& dataset_dir, const DatasetOptions& options = {});

}  // namespace lista::io
