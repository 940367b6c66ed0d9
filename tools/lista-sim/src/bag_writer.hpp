// Writes a simulated mission as a robot records it: one ROS bag (ROS 1 .bag,
// or a ROS 2 bag in .db3 or .mcap storage) with the clouds in the sensor
// frame, the estimated poses (drift included) as /tf and as an odometry
// topic, and beside it trajectory.txt, the same poses as a TUM file.
#pragma once

#include <lista/points.hpp>
#include <lista_bag/messages.hpp>

#include <memory>
#include <string>

namespace lista::sim {

// Names the bag's topics and frames use; tests and docs refer to them.
inline constexpr const char* kBagCloudTopic = "/points";
inline constexpr const char* kBagOdometryTopic = "/odom";
inline constexpr const char* kBagSensorFrame = "lidar";
inline constexpr double kBagStartTime = 1.7e9;  // s: a bag's stamps are wall-clock times, never 0

enum class BagFormat { ros1, ros2_sqlite3, ros2_mcap };

class MissionBagWriter {
 public:
  MissionBagWriter(const std::string& mission_dir, BagFormat format);
  // One sweep at `stamp` (s), its points in the sensor frame, its sensor
  // pose as the robot estimated it. `times` (empty, or one per point): each
  // point's time after `stamp`, s, written as a float32 field "time" as
  // Velodyne's driver does.
  void add(double stamp, const PointSet& points, const std::vector<float>& times, const Eigen::Isometry3d& estimated_sensor_pose);
  // A pose with no sweep (where the last skewed sweep ends): /tf and /odom.
  void add_pose(double stamp, const Eigen::Isometry3d& estimated_sensor_pose);
  // Finishes the bag (indexes, metadata).
  void close();

  // The sensor's mount on the robot's base (/tf_static base_link -> lidar).
  static Eigen::Isometry3d mount();

 private:
  std::unique_ptr<bag::Writer> writer_;
};

}  // namespace lista::sim
