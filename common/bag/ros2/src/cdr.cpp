#include "cdr.hpp"

#include "cdr_stream.hpp"

#include <lista/error.hpp>

#include <cmath>

namespace lista::bag::cdr {
namespace {

constexpr const char* kCloud = "sensor_msgs/msg/PointCloud2";
constexpr const char* kTf = "tf2_msgs/msg/TFMessage";
constexpr const char* kOdometry = "nav_msgs/msg/Odometry";
constexpr const char* kPose = "geometry_msgs/msg/PoseStamped";

// std_msgs/Header: builtin_interfaces/Time stamp + frame_id.
void read_header(Input& in, double& stamp, std::string& frame_id) {
  const int32_t sec = in.i32("header.stamp.sec");
  const uint32_t nanosec = in.u32("header.stamp.nanosec");
  stamp = sec + nanosec * 1e-9;
  frame_id = in.string("header.frame_id");
}

void write_header(Output& out, double stamp, const std::string& frame_id) {
  int32_t sec = 0;
  uint32_t nanosec = 0;
  split_stamp(stamp, sec, nanosec);
  out.i32(sec);
  out.u32(nanosec);
  out.string(frame_id);
}

// geometry_msgs Point/Vector3 then Quaternion (x, y, z, w) as one rigid
// transform; a quaternion that cannot be normalised is malformed data, not
// something to guess a rotation for.
Eigen::Isometry3d read_rigid(Input& in, const char* translation, const char* rotation) {
  Eigen::Vector3d t;
  for (int i = 0; i < 3; ++i) t[i] = in.f64(translation);
  double q[4];
  for (double& v : q) v = in.f64(rotation);
  if (!t.allFinite()) in.fail(translation, "is not finite");
  const auto iso = rigid_transform(t, q[0], q[1], q[2], q[3]);
  if (!iso) in.fail(rotation, "quaternion is zero or not finite, no rotation");
  return *iso;
}

void write_rigid(Output& out, const Eigen::Isometry3d& iso) {
  const Eigen::Quaterniond q(iso.rotation());
  for (int i = 0; i < 3; ++i) out.f64(iso.translation()[i]);
  out.f64(q.x());
  out.f64(q.y());
  out.f64(q.z());
  out.f64(q.w());
}

}  // namespace

void split_stamp(double seconds, int32_t& sec, uint32_t& nanosec) {
  const double whole = std::floor(seconds);
  if (!std::isfinite(seconds) || whole < -2147483648.0 || whole > 2147483647.0)
    throw Error("stamp " + std::to_string(seconds) + " s does not fit builtin_interfaces/Time");
  long long s = static_cast<long long>(whole);
  long long ns = std::llround((seconds - whole) * 1e9);
  if (ns >= 1000000000LL) {  // rounding carried into the next second
    ns -= 1000000000LL;
    ++s;
  }
  if (s > 2147483647LL) throw Error("stamp " + std::to_string(seconds) + " s does not fit builtin_interfaces/Time");
  sec = static_cast<int32_t>(s);
  nanosec = static_cast<uint32_t>(ns);
}

Cloud decode_cloud(const uint8_t* data, size_t size, bool headers_only) {
  Input in(data, size, kCloud);
  Cloud c;
  read_header(in, c.stamp, c.frame_id);
  c.height = in.u32("height");
  c.width = in.u32("width");
  // A PointField is at least a 4-byte name length, offset, datatype, count.
  const uint32_t n = in.count("fields", 13);
  c.fields.resize(n);
  for (PointField& f : c.fields) {
    f.name = in.string("fields[].name");
    f.offset = in.u32("fields[].offset");
    f.datatype = in.u8("fields[].datatype");
    f.count = in.u32("fields[].count");
  }
  c.is_bigendian = in.boolean("is_bigendian");
  c.point_step = in.u32("point_step");
  c.row_step = in.u32("row_step");
  in.bytes("data", c.data, !headers_only);
  c.is_dense = in.boolean("is_dense");
  return c;
}

std::vector<FrameTransform> decode_tf(const uint8_t* data, size_t size) {
  Input in(data, size, kTf);
  // A TransformStamped is at least 8 (stamp) + 2 * 5 (strings) + 56 (transform) bytes.
  const uint32_t n = in.count("transforms", 74);
  std::vector<FrameTransform> out(n);
  for (FrameTransform& t : out) {
    read_header(in, t.stamp, t.parent_frame);
    t.child_frame = in.string("transforms[].child_frame_id");
    t.transform = read_rigid(in, "transforms[].transform.translation", "transforms[].transform.rotation");
  }
  return out;
}

StampedPose decode_odometry(const uint8_t* data, size_t size) {
  Input in(data, size, kOdometry);
  StampedPose p;
  read_header(in, p.stamp, p.frame_id);
  p.child_frame = in.string("child_frame_id");
  p.pose = read_rigid(in, "pose.pose.position", "pose.pose.orientation");
  return p;
}

StampedPose decode_pose_stamped(const uint8_t* data, size_t size) {
  Input in(data, size, kPose);
  StampedPose p;
  read_header(in, p.stamp, p.frame_id);
  p.pose = read_rigid(in, "pose.position", "pose.orientation");
  return p;
}

std::vector<uint8_t> encode_cloud(const Cloud& c, bool big_endian) {
  Output out(big_endian);
  write_header(out, c.stamp, c.frame_id);
  out.u32(c.height);
  out.u32(c.width);
  out.u32(static_cast<uint32_t>(c.fields.size()));
  for (const PointField& f : c.fields) {
    out.string(f.name);
    out.u32(f.offset);
    out.u8(f.datatype);
    out.u32(f.count);
  }
  out.boolean(c.is_bigendian);
  out.u32(c.point_step);
  out.u32(c.row_step);
  out.bytes(c.data);
  out.boolean(c.is_dense);
  return out.take();
}

std::vector<uint8_t> encode_tf(const std::vector<FrameTransform>& transforms, bool big_endian) {
  Output out(big_endian);
  out.u32(static_cast<uint32_t>(transforms.size()));
  for (const FrameTransform& t : transforms) {
    write_header(out, t.stamp, t.parent_frame);
    out.string(t.child_frame);
    write_rigid(out, t.transform);
  }
  return out.take();
}

std::vector<uint8_t> encode_odometry(const StampedPose& p, bool big_endian) {
  Output out(big_endian);
  write_header(out, p.stamp, p.frame_id);
  out.string(p.child_frame);
  write_rigid(out, p.pose);
  for (int i = 0; i < 36; ++i) out.f64(0.0);      // pose.covariance
  for (int i = 0; i < 6; ++i) out.f64(0.0);       // twist.twist linear, angular
  for (int i = 0; i < 36; ++i) out.f64(0.0);      // twist.covariance
  return out.take();
}

std::vector<uint8_t> encode_pose_stamped(const StampedPose& p, bool big_endian) {
  Output out(big_endian);
  write_header(out, p.stamp, p.frame_id);
  write_rigid(out, p.pose);
  return out.take();
}

}  // namespace lista::bag::cdr
