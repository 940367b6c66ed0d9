// CDR coders of the four ROS 2 message types a mission needs. Decoders take
// the serialised message with its 4-byte encapsulation header, accept both
// byte orders and throw lista::Error naming the type and field on anything
// malformed (the caller adds file and topic). Encoders write little endian
// unless asked for big.
#pragma once

#include <lista_bag/messages.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lista::bag::cdr {

// sensor_msgs/msg/PointCloud2; headers_only leaves `data` empty (still checked
// to fit in the buffer).
Cloud decode_cloud(const uint8_t* data, size_t size, bool headers_only);
// tf2_msgs/msg/TFMessage.
std::vector<FrameTransform> decode_tf(const uint8_t* data, size_t size);
// nav_msgs/msg/Odometry: header, child_frame_id and pose.pose (the covariance
// and twist that follow are not read).
StampedPose decode_odometry(const uint8_t* data, size_t size);
// geometry_msgs/msg/PoseStamped (child_frame left empty).
StampedPose decode_pose_stamped(const uint8_t* data, size_t size);

std::vector<uint8_t> encode_cloud(const Cloud& cloud, bool big_endian = false);
std::vector<uint8_t> encode_tf(const std::vector<FrameTransform>& transforms, bool big_endian = false);
// Covariances and twist are written as zeros.
std::vector<uint8_t> encode_odometry(const StampedPose& pose, bool big_endian = false);
std::vector<uint8_t> encode_pose_stamped(const StampedPose& pose, bool big_endian = false);

// builtin_interfaces/Time <-> seconds; throws for a stamp outside int32 seconds.
void split_stamp(double seconds, int32_t& sec, uint32_t& nanosec);

}  // namespace lista::bag::cdr
