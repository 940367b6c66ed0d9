// The CDR coders: round trips of every type, both byte orders, and bad
// bytes answered with a lista::Error that names type and field.
#include "bag_fixtures.hpp"
#include "cdr.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

using namespace lista::bag;
using namespace lista_test;

TEST(Cdr, CloudRoundTripLittleEndian) {
  const Cloud c = sample_cloud(12.75);
  const std::vector<uint8_t> bytes = cdr::encode_cloud(c);
  ASSERT_GE(bytes.size(), 4u);
  EXPECT_EQ(bytes[0], 0);
  EXPECT_EQ(bytes[1], 1);  // CDR_LE
  expect_same_cloud(c, cdr::decode_cloud(bytes.data(), bytes.size(), false));
}

TEST(Cdr, CloudHeadersOnlyLeavesDataEmpty) {
  const Cloud c = sample_cloud(3.0);
  const std::vector<uint8_t> bytes = cdr::encode_cloud(c);
  expect_same_cloud(c, cdr::decode_cloud(bytes.data(), bytes.size(), true), false);
}

TEST(Cdr, TfRoundTrip) {
  const std::vector<FrameTransform> tf = sample_tf(4.5);
  const std::vector<uint8_t> bytes = cdr::encode_tf(tf);
  expect_same_tf(tf, cdr::decode_tf(bytes.data(), bytes.size()));
}

TEST(Cdr, OdometryRoundTripWritesZeroTwistAndCovariances) {
  const StampedPose p = sample_odometry(-1.25);  // negative stamps floor the seconds
  const std::vector<uint8_t> bytes = cdr::encode_odometry(p);
  expect_same_pose(p, cdr::decode_odometry(bytes.data(), bytes.size()));
  // The last 78 doubles: pose.covariance, twist.twist, twist.covariance.
  for (size_t i = bytes.size() - 78 * 8; i < bytes.size(); ++i) ASSERT_EQ(bytes[i], 0) << i;
}

TEST(Cdr, PoseStampedRoundTrip) {
  const StampedPose p = sample_pose(1700000000.123456789);
  const std::vector<uint8_t> bytes = cdr::encode_pose_stamped(p);
  const StampedPose back = cdr::decode_pose_stamped(bytes.data(), bytes.size());
  EXPECT_NEAR(back.stamp, p.stamp, 1e-6);
  EXPECT_TRUE(back.child_frame.empty());
  EXPECT_TRUE(back.pose.isApprox(p.pose, 1e-12));
}

TEST(Cdr, BigEndianEncodingDecodes) {
  const Cloud c = sample_cloud(8.0);
  const std::vector<uint8_t> bytes = cdr::encode_cloud(c, true);
  EXPECT_EQ(bytes[1], 0);  // CDR_BE
  expect_same_cloud(c, cdr::decode_cloud(bytes.data(), bytes.size(), false));
  const std::vector<uint8_t> tf = cdr::encode_tf(sample_tf(2.0), true);
  expect_same_tf(sample_tf(2.0), cdr::decode_tf(tf.data(), tf.size()));
}

namespace {
void put_be(std::vector<uint8_t>& b, const void* v, size_t n) {
  const auto* p = static_cast<const uint8_t*>(v);
  for (size_t i = 0; i < n; ++i) b.push_back(p[n - 1 - i]);  // this test machine is little endian
}
}  // namespace

// geometry_msgs/PoseStamped in CDR_BE by hand: the 7 bytes of padding after
// "odom\0" put the doubles on 8 bytes counted from after the header.
TEST(Cdr, HandBuiltBigEndianPoseStamped) {
  std::vector<uint8_t> b = {0x00, 0x00, 0x00, 0x00};
  const int32_t sec = 5;
  const uint32_t nanosec = 250000000, len = 5;
  put_be(b, &sec, 4);
  put_be(b, &nanosec, 4);
  put_be(b, &len, 4);
  for (char ch : std::string("odom")) b.push_back(static_cast<uint8_t>(ch));
  b.push_back(0);
  b.insert(b.end(), 7, 0xAA);  // padding bytes are not read
  const double s = std::sqrt(0.5);
  for (double v : {1.0, -2.0, 3.5, 0.0, 0.0, s, s}) put_be(b, &v, 8);
  ASSERT_EQ(b.size(), 4u + 24 + 56);
  const StampedPose p = cdr::decode_pose_stamped(b.data(), b.size());
  EXPECT_DOUBLE_EQ(p.stamp, 5.25);
  EXPECT_EQ(p.frame_id, "odom");
  EXPECT_TRUE(p.pose.translation().isApprox(Eigen::Vector3d(1.0, -2.0, 3.5)));
  EXPECT_TRUE(p.pose.linear().isApprox(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(), 1e-12));
}

TEST(Cdr, EveryTruncationIsAnError) {
  const std::vector<uint8_t> cloud = cdr::encode_cloud(sample_cloud(1.0));
  const std::vector<uint8_t> tf = cdr::encode_tf(sample_tf(1.0));
  const std::vector<uint8_t> pose = cdr::encode_pose_stamped(sample_pose(1.0));
  const std::vector<uint8_t> odom = cdr::encode_odometry(sample_odometry(1.0));
  for (size_t n = 0; n < cloud.size(); ++n) {
    EXPECT_THROW(cdr::decode_cloud(cloud.data(), n, false), lista::Error) << n;
    EXPECT_THROW(cdr::decode_cloud(cloud.data(), n, true), lista::Error) << n;
  }
  for (size_t n = 0; n < tf.size(); ++n) EXPECT_THROW(cdr::decode_tf(tf.data(), n), lista::Error) << n;
  for (size_t n = 0; n < pose.size(); ++n) EXPECT_THROW(cdr::decode_pose_stamped(pose.data(), n), lista::Error) << n;
  // Odometry ends with the pose: what follows it (covariance, twist) is not read.
  for (size_t n = 0; n < odom.size() - 78 * 8; ++n) EXPECT_THROW(cdr::decode_odometry(odom.data(), n), lista::Error) << n;
  const std::string e = error_of([&] { cdr::decode_cloud(cloud.data(), cloud.size() - 3, false); });
  EXPECT_NE(e.find("sensor_msgs/msg/PointCloud2"), std::string::npos) << e;
  EXPECT_NE(e.find("data"), std::string::npos) << e;
}

TEST(Cdr, ForgedCountsAreRefusedBeforeAllocating) {
  std::vector<uint8_t> tf = cdr::encode_tf(sample_tf(1.0));
  const uint32_t huge = 0xFFFFFFF0u;
  std::memcpy(&tf[4], &huge, 4);  // transforms count
  std::string e = error_of([&] { cdr::decode_tf(tf.data(), tf.size()); });
  EXPECT_NE(e.find("transforms"), std::string::npos) << e;
  EXPECT_NE(e.find("4294967280"), std::string::npos) << e;

  Cloud c = sample_cloud(1.0);
  c.data.clear();
  std::vector<uint8_t> cloud = cdr::encode_cloud(c);
  // The data length is the uint32 just before the final is_dense byte.
  std::memcpy(&cloud[cloud.size() - 5], &huge, 4);
  e = error_of([&] { cdr::decode_cloud(cloud.data(), cloud.size(), true); });
  EXPECT_NE(e.find("data"), std::string::npos) << e;
}

TEST(Cdr, StringsMustBeNulTerminated) {
  std::vector<uint8_t> pose = cdr::encode_pose_stamped(sample_pose(1.0));
  // frame_id "map": length at 12, bytes at 16..19 with the NUL at 19.
  ASSERT_EQ(pose[19], 0);
  pose[19] = 'x';
  std::string e = error_of([&] { cdr::decode_pose_stamped(pose.data(), pose.size()); });
  EXPECT_NE(e.find("header.frame_id"), std::string::npos) << e;
  EXPECT_NE(e.find("NUL"), std::string::npos) << e;
  const uint32_t zero = 0;
  std::memcpy(&pose[12], &zero, 4);
  e = error_of([&] { cdr::decode_pose_stamped(pose.data(), pose.size()); });
  EXPECT_NE(e.find("length 0"), std::string::npos) << e;
}

TEST(Cdr, ZeroQuaternionAndOtherEncapsulationsAreErrors) {
  std::vector<uint8_t> pose = cdr::encode_pose_stamped(sample_pose(1.0));
  std::fill(pose.end() - 32, pose.end(), 0);  // orientation x, y, z, w
  std::string e = error_of([&] { cdr::decode_pose_stamped(pose.data(), pose.size()); });
  EXPECT_NE(e.find("quaternion"), std::string::npos) << e;
  EXPECT_NE(e.find("geometry_msgs/msg/PoseStamped"), std::string::npos) << e;

  std::vector<uint8_t> xcdr2 = cdr::encode_pose_stamped(sample_pose(1.0));
  xcdr2[1] = 0x07;  // PL_CDR2_LE
  e = error_of([&] { cdr::decode_pose_stamped(xcdr2.data(), xcdr2.size()); });
  EXPECT_NE(e.find("encapsulation"), std::string::npos) << e;
}

TEST(Cdr, StampsOutsideBuiltinTimeAreRefused) {
  StampedPose p = sample_pose(1.0);
  p.stamp = 1e12;
  EXPECT_THROW(cdr::encode_pose_stamped(p), lista::Error);
  p.stamp = std::nan("");
  EXPECT_THROW(cdr::encode_pose_stamped(p), lista::Error);
  int32_t sec = 0;
  uint32_t ns = 0;
  cdr::split_stamp(2.9999999999, sec, ns);  // rounds up into the next second
  EXPECT_EQ(sec, 3);
  EXPECT_EQ(ns, 0u);
}
