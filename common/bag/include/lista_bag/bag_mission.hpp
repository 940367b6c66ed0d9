// A mission recorded as ROS bags (ROS 1 .bag files, or a ROS 2 bag: .db3 or
// .mcap), read into the same Mission a folder of scans gives.
#pragma once

#include <lista/missions.hpp>
#include <lista_io/dataset.hpp>

#include <string>

namespace lista::bag {

// Where a bag mission's clouds and poses come from. Each key may be set in a
// mission.toml beside the bags (that mission only) or as io.missions
// parameters (every bag mission); empty = found from the bag.
struct BagOptions {
  std::string cloud_topic;  // "" = the only sensor_msgs/PointCloud2 topic
  // "tf", an odometry or pose topic, or a TUM file (relative to the mission
  // folder). "" = tf when the cloud's frame hangs under a moving tf frame,
  // else the only nav_msgs/Odometry or geometry_msgs/PoseStamped topic.
  std::string poses;
  std::string fixed_frame;  // with tf: the map frame; "" = the root of the cloud frame's tree
  // With a pose topic or file: the frame they give poses of; "" = the
  // odometry's child frame, else the cloud's frame. The sensor is placed
  // through tf's body -> cloud frame transform when tf has one.
  std::string body_frame;
  // Clouds with per-point times (cloud_points.hpp) are deskewed: each point
  // moved into the sensor frame at the cloud's stamp by the poses' motion,
  // when the poses are sampled at least every two sweeps.
  bool deskew = true;
};

// What reading one bag mission found, for the run's messages.
struct BagMissionLog {
  std::string bag;            // the file or folder read
  std::string cloud_topic;
  std::string pose_source;    // e.g. "tf (map -> velodyne)", "/odom", "trajectory.txt"
  size_t clouds = 0;          // on the cloud topic
  uint64_t cloud_points = 0;  // in all of them (width x height), read or not
  size_t outside_poses = 0;   // skipped: stamp outside the poses' time range
  size_t timed = 0, deskewed = 0;  // read clouds with per-point times, and those deskewed
  std::vector<std::string> notes;  // assumptions worth a line (no body -> sensor tf, ...)
};

// Reads `mission_dir` (lista::io::is_bag_mission). `defaults` are the
// io.missions parameters; a mission.toml there overrides them, and its
// scan_spacing overrides options.scan_spacing. Clouds are thinned as folder
// missions are (io::spacing_for): those not read keep their pose and no
// points. Throws lista::Error naming the file, topic or frame.
Mission read_bag_mission(const std::string& mission_dir, const io::DatasetOptions& options, const BagOptions& defaults,
                         BagMissionLog* log = nullptr);

}  // namespace lista::bag
