// The few ROS message types a mission needs, decoded into plain structs that
// do not depend on ROS 1 or ROS 2 headers, and the reader/writer interface
// every bag storage (ROS 1 .bag, ROS 2 .db3 / .mcap) implements.
#pragma once

#include <Eigen/Geometry>

#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace lista::bag {

// sensor_msgs/PointField datatype codes (same numbers in ROS 1 and ROS 2).
enum PointFieldType : uint8_t { int8 = 1, uint8 = 2, int16 = 3, uint16 = 4, int32 = 5, uint32 = 6, float32 = 7, float64 = 8 };

struct PointField {
  std::string name;
  uint32_t offset = 0;
  uint8_t datatype = 0;  // PointFieldType
  uint32_t count = 1;
};

// sensor_msgs/PointCloud2. `data` is left empty when a reader is asked for
// headers only.
struct Cloud {
  double stamp = 0.0;  // header.stamp, seconds
  std::string frame_id;
  uint32_t height = 0, width = 0, point_step = 0, row_step = 0;
  bool is_bigendian = false, is_dense = false;
  std::vector<PointField> fields;
  std::vector<uint8_t> data;
};

// One geometry_msgs/TransformStamped of a tf2_msgs/TFMessage: maps points of
// child_frame into parent_frame (header.frame_id).
struct FrameTransform {
  double stamp = 0.0;
  std::string parent_frame, child_frame;
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
};

// nav_msgs/Odometry (child_frame set) or geometry_msgs/PoseStamped (child
// empty): the pose of the child (the body) in frame_id.
struct StampedPose {
  double stamp = 0.0;
  std::string frame_id, child_frame;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

enum class MessageKind { point_cloud, tf, tf_static, odometry, pose_stamped, other };

struct TopicInfo {
  std::string name;
  std::string type;  // as the bag spells it: "sensor_msgs/PointCloud2" or "sensor_msgs/msg/PointCloud2"
  MessageKind kind = MessageKind::other;
  uint64_t messages = 0;
};

// A message's translation and rotation quaternion (x, y, z, w) as a rigid
// transform, the quaternion normalised; nullopt when it cannot be (zero or
// not finite) or the translation is not finite: malformed data, not a
// rotation to guess. Every reader converts through this one.
inline std::optional<Eigen::Isometry3d> rigid_transform(const Eigen::Vector3d& t, double qx, double qy, double qz, double qw) {
  const Eigen::Quaterniond q(qw, qx, qy, qz);
  const double norm = q.norm();
  if (!std::isfinite(norm) || norm < 1e-9 || !t.allFinite()) return std::nullopt;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

// The kind of a type name in either spelling ("nav_msgs/Odometry",
// "nav_msgs/msg/Odometry"); tf_static is told apart by topic name, not type.
inline MessageKind kind_of(const std::string& topic, const std::string& type) {
  std::string t = type;
  if (const auto at = t.find("/msg/"); at != std::string::npos) t.replace(at, 5, "/");
  if (t == "sensor_msgs/PointCloud2") return MessageKind::point_cloud;
  if (t == "tf2_msgs/TFMessage" || t == "tf/tfMessage") return topic == "/tf_static" ? MessageKind::tf_static : MessageKind::tf;
  if (t == "nav_msgs/Odometry") return MessageKind::odometry;
  if (t == "geometry_msgs/PoseStamped") return MessageKind::pose_stamped;
  return MessageKind::other;
}

// What a reader hands out, in the bag's record-time order. A callback left
// empty skips those messages without decoding them.
struct Visitor {
  std::function<void(const std::string& topic, Cloud&&)> cloud;
  std::function<void(const std::string& topic, std::vector<FrameTransform>&&, bool is_static)> tf;
  std::function<void(const std::string& topic, StampedPose&&)> pose;  // odometry and pose_stamped
};

class Reader {
 public:
  virtual ~Reader() = default;
  virtual std::vector<TopicInfo> topics() const = 0;
  // Streams the messages of `topics` (names from topics()) to the visitor;
  // with clouds_headers_only, clouds come without `data` (cheap first pass).
  // Throws lista::Error naming the file (and topic) on anything malformed.
  virtual void read(const std::vector<std::string>& topics, const Visitor& visitor, bool clouds_headers_only) = 0;
  // The file or folder read, for messages.
  virtual std::string path() const = 0;
};

class Writer {
 public:
  virtual ~Writer() = default;
  // `record_time`: when the bag recorder received it (seconds).
  virtual void write_cloud(const std::string& topic, const Cloud& cloud, double record_time) = 0;
  virtual void write_tf(const std::string& topic, const std::vector<FrameTransform>& transforms, double record_time) = 0;
  virtual void write_odometry(const std::string& topic, const StampedPose& pose, double record_time) = 0;
  virtual void write_pose_stamped(const std::string& topic, const StampedPose& pose, double record_time) = 0;
  // Finishes the files (indexes, metadata); the destructor does too, but
  // cannot report a failure.
  virtual void close() = 0;
};

}  // namespace lista::bag
