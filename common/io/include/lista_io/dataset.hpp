// Reading a dataset of missions (data contract, sect. 1).
#pragma once

#include <lista/missions.hpp>

#include <functional>
#include <string>
#include <vector>

namespace lista::io {

struct DatasetOptions {
  std::vector<std::string> missions;  // names to read, in this order; empty = all, sorted
  bool load_points = true;            // false: poses and file lists only
  int threads = 1;
  // Dense logs (a 10 Hz LiDAR): with scan_spacing > 0 a scan's points are
  // read only where scans_to_read keeps it; the others stay in the mission
  // with their pose and no points (points_in_file 0).
  double scan_spacing = 0.0;   // m
  double scan_turn_deg = 30.0;
  // With scan_spacing 0, a dense log (is_dense_log) is read as with
  // scan_spacing = dense_spacing; 0 reads it whole. 0 here so that tools
  // which score or inspect a dataset see every point; io.missions turns it on.
  double dense_spacing = 0.0;  // m
  // Reads a mission recorded as ROS bags (is_bag_mission): liblista_bag's
  // reader, set by those who link it (io.missions, lista-eval); unset, such
  // a mission is an error that says so.
  std::function<Mission(const std::string& mission_dir, const struct DatasetOptions& options)> read_bag_mission = nullptr;
};

// The recording a mission folder holds, if it is a bag mission: its ROS 1
// .bag files (sorted), or the ROS 2 bag to open: the folder itself or its
// only subfolder when it holds metadata.yaml, or its one .db3 / .mcap file.
// Both empty for a folder of the data contract. Throws lista::Error for a
// folder holding both kinds, or several ROS 2 storage files without
// metadata.yaml.
struct BagRecording {
  std::vector<std::string> ros1_files;
  std::string ros2;
  bool empty() const { return ros1_files.empty() && ros2.empty(); }
};
BagRecording bag_recording(const std::string& mission_dir);
bool is_bag_mission(const std::string& mission_dir);  // !bag_recording(dir).empty()

// A dense log: at least kDenseLogScans scans whose sensors lie under
// kDenseLogStep apart at the median (a 10 Hz LiDAR at walking pace, or a
// robot standing still). Each scan adds little there but costs every stage.
constexpr size_t kDenseLogScans = 500;
constexpr double kDenseLogStep = 0.1;  // m

// Median distance between consecutive sensor positions; 0 for fewer than two.
double median_step(const std::vector<Eigen::Isometry3d>& poses);
bool is_dense_log(const std::vector<Eigen::Isometry3d>& poses);
// The spacing a trajectory is thinned with: scan_spacing when set, else
// dense_spacing when it is a dense log, else 0 (every scan).
double spacing_for(const std::vector<Eigen::Isometry3d>& poses, const DatasetOptions& options);

// Which scans of a trajectory to read: the first, the last, and each whose
// sensor lies at least `spacing` from the last one kept or has turned at
// least `turn_deg` from it. All of them when spacing <= 0.
std::vector<char> scans_to_read(const std::vector<Eigen::Isometry3d>& poses, double spacing, double turn_deg);

// A mission folder without poses.txt holds map-frame .pcd scans carrying
// their sensor pose in VIEWPOINT (the KTH layout).
bool is_viewpoint_layout(const std::string& mission_dir);

// The mission folders of a dataset (sorted names), or the dataset itself when
// it is a single VIEWPOINT-layout folder. Throws lista::Error if none.
std::vector<std::string> list_missions(const std::string& dataset_dir);

// Reads one mission folder: poses.txt + scans/ (or the VIEWPOINT layout),
// poses_gt.txt when present. Errors: scan count != pose count, unreadable or
// malformed file, non-orthonormal rotation, empty mission.
Mission read_mission(const std::string& mission_dir, const DatasetOptions& options = {});

MissionSet read_dataset(const std::string& dataset_dir, const DatasetOptions& options = {});

}  // namespace lista::io
