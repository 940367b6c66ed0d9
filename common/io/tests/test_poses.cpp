#include "test_util.hpp"

#include <lista_io/poses.hpp>

using namespace lista::io;
using namespace lista_io_test;

namespace {
std::vector<PoseRecord> sample_poses() {
  std::vector<PoseRecord> v;
  for (int i = 0; i < 5; ++i) {
    PoseRecord r;
    r.timestamp = 100.0 + 0.1 * i;
    r.pose.setIdentity();
    r.pose.translate(Eigen::Vector3d(i, -2.0 * i, 0.3));
    r.pose.rotate(Eigen::AngleAxisd(0.4 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    v.push_back(r);
  }
  return v;
}
}  // namespace

TEST(Poses, TumAndKittiRoundTrip) {
  const auto dir = temp_dir("poses");
  const auto poses = sample_poses();
  for (auto fmt : {PoseFormat::tum, PoseFormat::kitti}) {
    const std::string path = (dir / "p.txt").string();
    write_poses(path, poses, fmt);
    const auto back = read_poses(path);
    ASSERT_EQ(back.size(), poses.size());
    for (size_t i = 0; i < poses.size(); ++i) {
      EXPECT_TRUE(back[i].pose.isApprox(poses[i].pose, 1e-12)) << i;
      EXPECT_DOUBLE_EQ(back[i].timestamp, fmt == PoseFormat::tum ? poses[i].timestamp : double(i));
    }
  }
}

TEST(Poses, CommentsAndBlankLinesAreSkipped) {
  const auto dir = temp_dir("poses");
  write_text(dir / "p.txt", "# timestamp tx ty tz qx qy qz qw\n\n1.5 1 2 3 0 0 0 1  # start\n2.5 4 5 6 0 0 1 0\n");
  const auto p = read_poses((dir / "p.txt").string());
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1].pose.translation(), Eigen::Vector3d(4, 5, 6));
  EXPECT_TRUE(p[1].pose.rotation().isApprox(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix()));
  EXPECT_EQ(p[0].timestamp, 1.5);
}

TEST(Poses, MalformedLinesNameFileAndLine) {
  const auto dir = temp_dir("poses");
  write_text(dir / "a.txt", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");
  expect_error([&] { read_poses((dir / "a.txt").string()); }, "a.txt:2: expected 8 fields");
  write_text(dir / "b.txt", "1 0 0 0 0 0 0 1\n# c\n1 0 0 0 0 1 0 0 0 0 1 0\n");
  expect_error([&] { read_poses((dir / "b.txt").string()); }, "b.txt:3: mixed pose layouts");
  write_text(dir / "c.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 2 0 0 0 0 1 0\n");
  expect_error([&] { read_poses((dir / "c.txt").string()); }, "c.txt:2: rotation is not orthonormal");
  write_text(dir / "d.txt", "1 0 0 0 0 0 0.5 0.5\n");
  expect_error([&] { read_poses((dir / "d.txt").string()); }, "d.txt:1: rotation quaternion has norm");
  write_text(dir / "e.txt", "1 0 zero 0 0 0 0 1\n");
  expect_error([&] { read_poses((dir / "e.txt").string()); }, "e.txt:1: field 3 'zero' is not a finite number");
  write_text(dir / "f.txt", "-1 0 0 0 0 1 0 0 0 0 1 0\n");  // a reflection
  expect_error([&] { read_poses((dir / "f.txt").string()); }, "f.txt:1: rotation is a reflection (det R = -1)");
  write_text(dir / "g.txt", "1,0,0,0,0,0,0,1\n");
  expect_error([&] { read_poses((dir / "g.txt").string()); }, "got 1; fields are separated by spaces, not commas");
  write_text(dir / "g2.txt", "1, 0, 0, 0, 0, 0, 0, 1\n");
  expect_error([&] { read_poses((dir / "g2.txt").string()); }, "'1,' is not a finite number; fields are separated by spaces");
  write_text(dir / "x.txt", "1 0x10 0 0 0 0 0 1\n");  // strtod would read 16
  expect_error([&] { read_poses((dir / "x.txt").string()); }, "x.txt:1: field 2 '0x10' is not a finite number (decimal");
  expect_error([&] { read_poses((dir / "none.txt").string()); }, "none.txt: cannot read");
  write_text(dir / "h.txt", "1 500000 5500000 300 0 0 0 1\n2 1e20 0 0 0 0 0 1\n");  // UTM fine, 1e20 not
  expect_error([&] { read_poses((dir / "h.txt").string()); }, "h.txt:2: position (1e20, 0, 0) lies more than 1e8 m");
}

TEST(Poses, AByteOrderMarkIsSkipped) {
  const auto dir = temp_dir("poses");
  write_text(dir / "bom.txt", "\xEF\xBB\xBF" "0 1 2 3 0 0 0 1\n");
  const auto p = read_poses((dir / "bom.txt").string());
  ASSERT_EQ(p.size(), 1u);
  EXPECT_EQ(p[0].pose.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(Poses, SlightlyOffRotationIsReorthonormalised) {
  const auto dir = temp_dir("poses");
  write_text(dir / "p.txt", "1.0002 0 0 0 0 1 0 0 0 0 1 0\n");
  const auto p = read_poses((dir / "p.txt").string());
  const Eigen::Matrix3d R = p[0].pose.rotation();
  EXPECT_TRUE((R.transpose() * R).isIdentity(1e-12));
}
