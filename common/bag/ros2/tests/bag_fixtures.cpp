#include "bag_fixtures.hpp"

#include "cdr.hpp"

#include <lista/error.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace fs = std::filesystem;
using namespace lista::bag;

namespace lista_test {

ScratchDir::ScratchDir() {
  const char* tmp = std::getenv("TMPDIR");
  std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/lista-ros2bag-XXXXXX";
  if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
  dir_ = pattern;
}

ScratchDir::~ScratchDir() {
  std::error_code ec;
  fs::remove_all(dir_, ec);
}

namespace {
Eigen::Isometry3d rigid(double yaw, double pitch, const Eigen::Vector3d& t) {
  Eigen::Isometry3d iso = Eigen::Isometry3d::Identity();
  iso.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY())).toRotationMatrix();
  iso.translation() = t;
  return iso;
}
}  // namespace

Cloud sample_cloud(double stamp) {
  Cloud c;
  c.stamp = stamp;
  c.frame_id = "lidar";
  c.height = 1;
  c.width = 3;
  c.point_step = 16;
  c.row_step = 48;
  c.is_dense = true;
  c.fields = {{"x", 0, float32, 1}, {"y", 4, float32, 1}, {"z", 8, float32, 1}, {"intensity", 12, uint16, 1}};
  for (int i = 0; i < 48; ++i) c.data.push_back(static_cast<uint8_t>(i * 7 + int(stamp)));
  return c;
}

std::vector<FrameTransform> sample_tf(double stamp) {
  FrameTransform a;
  a.stamp = stamp;
  a.parent_frame = "odom";
  a.child_frame = "base_link";
  a.transform = rigid(0.5, 0.0, {1.0, 2.0, 3.0 + stamp});
  FrameTransform b = a;
  b.parent_frame = "base_link";
  b.child_frame = "lidar";
  b.transform = rigid(-0.25, 0.1, {0.2, 0.0, 1.5});
  return {a, b};
}

StampedPose sample_odometry(double stamp) {
  StampedPose p;
  p.stamp = stamp;
  p.frame_id = "odom";
  p.child_frame = "base_link";
  p.pose = rigid(1.25, -0.3, {4.0, -5.0, 0.5});
  return p;
}

StampedPose sample_pose(double stamp) {
  StampedPose p;
  p.stamp = stamp;
  p.frame_id = "map";
  p.pose = rigid(-2.0, 0.2, {-1.0, 7.0, 2.0});
  return p;
}

void write_samples(Writer& w) {
  std::vector<FrameTransform> stat = sample_tf(10.0);
  stat.resize(1);
  w.write_tf("/tf_static", stat, 10.0);
  w.write_tf("/tf", sample_tf(10.5), 10.5);
  w.write_odometry("/odom", sample_odometry(11.0), 11.0);
  w.write_pose_stamped("/pose", sample_pose(11.5), 11.5);
  w.write_cloud("/points", sample_cloud(12.0), 12.0);
  w.write_tf("/tf", sample_tf(12.5), 12.5);
  w.write_cloud("/points", sample_cloud(13.0), 13.0);
}

void write_samples(lista::bag::ros2::StorageWriter& w) {
  std::vector<FrameTransform> stat = sample_tf(10.0);
  stat.resize(1);
  const auto ns = [](double s) { return static_cast<int64_t>(std::llround(s * 1e9)); };
  w.write("/tf_static", "tf2_msgs/msg/TFMessage", ns(10.0), cdr::encode_tf(stat));
  w.write("/tf", "tf2_msgs/msg/TFMessage", ns(10.5), cdr::encode_tf(sample_tf(10.5)));
  w.write("/odom", "nav_msgs/msg/Odometry", ns(11.0), cdr::encode_odometry(sample_odometry(11.0)));
  w.write("/pose", "geometry_msgs/msg/PoseStamped", ns(11.5), cdr::encode_pose_stamped(sample_pose(11.5)));
  w.write("/points", "sensor_msgs/msg/PointCloud2", ns(12.0), cdr::encode_cloud(sample_cloud(12.0)));
  w.write("/tf", "tf2_msgs/msg/TFMessage", ns(12.5), cdr::encode_tf(sample_tf(12.5)));
  w.write("/points", "sensor_msgs/msg/PointCloud2", ns(13.0), cdr::encode_cloud(sample_cloud(13.0)));
}

Collected read_all(Reader& reader, bool headers_only) {
  Collected got;
  std::vector<std::string> names;
  for (const TopicInfo& t : reader.topics()) names.push_back(t.name);
  Visitor v;
  v.cloud = [&](const std::string& topic, Cloud&& c) {
    got.order.push_back(topic);
    got.clouds.push_back(std::move(c));
  };
  v.tf = [&](const std::string& topic, std::vector<FrameTransform>&& tf, bool is_static) {
    got.order.push_back(topic);
    got.tfs.push_back(std::move(tf));
    got.tf_static.push_back(is_static);
  };
  v.pose = [&](const std::string& topic, StampedPose&& p) {
    got.order.push_back(topic);
    got.poses.push_back(std::move(p));
  };
  reader.read(names, v, headers_only);
  return got;
}

void expect_same_cloud(const Cloud& a, const Cloud& b, bool with_data) {
  EXPECT_DOUBLE_EQ(a.stamp, b.stamp);
  EXPECT_EQ(a.frame_id, b.frame_id);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.point_step, b.point_step);
  EXPECT_EQ(a.row_step, b.row_step);
  EXPECT_EQ(a.is_bigendian, b.is_bigendian);
  EXPECT_EQ(a.is_dense, b.is_dense);
  ASSERT_EQ(a.fields.size(), b.fields.size());
  for (size_t i = 0; i < a.fields.size(); ++i) {
    EXPECT_EQ(a.fields[i].name, b.fields[i].name);
    EXPECT_EQ(a.fields[i].offset, b.fields[i].offset);
    EXPECT_EQ(a.fields[i].datatype, b.fields[i].datatype);
    EXPECT_EQ(a.fields[i].count, b.fields[i].count);
  }
  if (with_data) EXPECT_EQ(a.data, b.data);
  else EXPECT_TRUE(b.data.empty());
}

void expect_same_pose(const StampedPose& a, const StampedPose& b) {
  EXPECT_NEAR(a.stamp, b.stamp, 1e-9);
  EXPECT_EQ(a.frame_id, b.frame_id);
  EXPECT_EQ(a.child_frame, b.child_frame);
  EXPECT_TRUE(a.pose.isApprox(b.pose, 1e-12)) << a.pose.matrix() << "\nvs\n" << b.pose.matrix();
}

void expect_same_tf(const std::vector<FrameTransform>& a, const std::vector<FrameTransform>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i].stamp, b[i].stamp, 1e-9);
    EXPECT_EQ(a[i].parent_frame, b[i].parent_frame);
    EXPECT_EQ(a[i].child_frame, b[i].child_frame);
    EXPECT_TRUE(a[i].transform.isApprox(b[i].transform, 1e-12));
  }
}

void expect_samples(const Collected& got, bool headers_only) {
  const std::vector<std::string> order = {"/tf_static", "/tf", "/odom", "/pose", "/points", "/tf", "/points"};
  EXPECT_EQ(got.order, order);
  ASSERT_EQ(got.clouds.size(), 2u);
  expect_same_cloud(sample_cloud(12.0), got.clouds[0], !headers_only);
  expect_same_cloud(sample_cloud(13.0), got.clouds[1], !headers_only);
  ASSERT_EQ(got.tfs.size(), 3u);
  std::vector<FrameTransform> stat = sample_tf(10.0);
  stat.resize(1);
  expect_same_tf(stat, got.tfs[0]);
  expect_same_tf(sample_tf(10.5), got.tfs[1]);
  expect_same_tf(sample_tf(12.5), got.tfs[2]);
  EXPECT_EQ(got.tf_static, (std::vector<bool>{true, false, false}));
  ASSERT_EQ(got.poses.size(), 2u);
  expect_same_pose(sample_odometry(11.0), got.poses[0]);
  expect_same_pose(sample_pose(11.5), got.poses[1]);
}

std::vector<uint8_t> read_bytes(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& file, const std::vector<uint8_t>& bytes) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace lista_test
