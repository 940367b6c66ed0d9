// Bag missions end to end through the real rosbag library: small bags written
// here, read back as Missions.
#include <gtest/gtest.h>
#include <lista/error.hpp>
#include <lista_bag/bag_mission.hpp>
#include <lista_bag/ros1.hpp>
#include <lista_io/poses.hpp>
#include <lista_io/test_scratch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>

using namespace lista;
using namespace lista::bag;
namespace fs = std::filesystem;

namespace {

constexpr double t0 = 1.7e9;

fs::path fresh_dir(const std::string& name) {
  const auto dir = io::testing::scratch_path("bag_" + name);
  fs::create_directories(dir);
  return dir;
}

Cloud cloud_at(double stamp, const std::string& frame, float x) {
  Cloud c;
  c.stamp = stamp;
  c.frame_id = frame;
  c.height = 1, c.width = 2, c.point_step = 12, c.row_step = 24;
  c.fields = {{"x", 0, float32, 1}, {"y", 4, float32, 1}, {"z", 8, float32, 1}};
  c.data.resize(24);
  const float v[6] = {x, 0, 0, x, 1, 0};
  std::memcpy(c.data.data(), v, 24);
  return c;
}

Eigen::Isometry3d pose_xyz_yaw(double x, double y, double z, double yaw_deg) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

const Eigen::Isometry3d kMount = pose_xyz_yaw(0.2, 0, 0.5, 90);

// Base poses at t0 + 0, 1, 2 s: 1 m a second along x, turning 10 deg a second.
Eigen::Isometry3d base_at(double s) { return pose_xyz_yaw(s, 0, 0, 10 * s); }

// Clouds at t0 + 0, 0.5, 1, 1.5, 2 and 3 (the last one after the poses end).
void write_clouds(Writer& w, const std::string& topic = "/points") {
  for (double s : {0.0, 0.5, 1.0, 1.5, 2.0, 3.0}) w.write_cloud(topic, cloud_at(t0 + s, "lidar", float(s)), t0 + s);
}

void write_tf(Writer& w) {
  w.write_tf("/tf_static", {{t0, "map", "odom", Eigen::Isometry3d::Identity()}, {t0, "base_link", "lidar", kMount}}, t0);
  for (double s : {0.0, 1.0, 2.0}) w.write_tf("/tf", {{t0 + s, "odom", "base_link", base_at(s)}}, t0 + s);
}

template <class Fn>
void expect_error(Fn fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "no error thrown, expected one containing '" << needle << "'";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

void expect_near(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, const std::string& what) {
  EXPECT_LT((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), 1e-9) << what << "\n" << a.matrix() << "\n" << b.matrix();
}

Mission read(const fs::path& dir, const BagOptions& o = {}, BagMissionLog* log = nullptr) {
  io::DatasetOptions opt;
  return read_bag_mission(dir.string(), opt, o, log);
}

}  // namespace

TEST(BagMission, PlacesEachCloudByTfAtItsStampAndSkipsThoseOutsideThePoses) {
  const auto dir = fresh_dir("tf");
  {
    auto w = create_ros1((dir / "a.bag").string());
    write_tf(*w);
    write_clouds(*w);
    w->close();
  }
  EXPECT_TRUE(io::is_bag_mission(dir.string()));
  BagMissionLog log;
  const Mission m = read(dir, {}, &log);
  EXPECT_EQ(log.cloud_topic, "/points");
  EXPECT_EQ(log.pose_source, "tf (map -> lidar)");
  EXPECT_EQ(log.clouds, 6u);
  EXPECT_EQ(log.outside_poses, 1u) << "the cloud at t0 + 3 s lies after the last pose";
  ASSERT_EQ(m.scans.size(), 5u);
  expect_near(m.scans[2].pose, base_at(1) * kMount, "a cloud on a tf stamp");
  // Half way: translation half way, yaw half way (slerp).
  expect_near(m.scans[1].pose, base_at(0.5) * kMount, "a cloud between two tf stamps");
  EXPECT_DOUBLE_EQ(m.scans[3].timestamp, t0 + 1.5);
  ASSERT_TRUE(m.scans[4].points);
  ASSERT_EQ(m.scans[4].points->size(), 2u);
  EXPECT_FLOAT_EQ(m.scans[4].points->xyz[0].x(), 2.0f) << "points stay in the sensor frame";
  EXPECT_EQ(m.scans[4].points_in_file, 2u);
}

TEST(BagMission, FallsBackToTheOnlyOdometryTopicAndMountsTheSensorThroughTfStatic) {
  const auto dir = fresh_dir("odom");
  {
    auto w = create_ros1((dir / "a.bag").string());
    w->write_tf("/tf_static", {{t0, "base_link", "lidar", kMount}}, t0);
    for (double s : {0.0, 1.0, 2.0}) w->write_odometry("/odom", {t0 + s, "odom", "base_link", base_at(s)}, t0 + s);
    write_clouds(*w);
    w->close();
  }
  BagMissionLog log;
  const Mission m = read(dir, {}, &log);
  EXPECT_EQ(log.pose_source, "/odom") << "lidar hangs under base_link by a static transform only: tf cannot place it";
  ASSERT_EQ(m.scans.size(), 5u);
  expect_near(m.scans[3].pose, base_at(1.5) * kMount, "odometry interpolated, then the mount");
  EXPECT_TRUE(log.notes.empty());
}

TEST(BagMission, TakesPosesFromATumFileNamedInMissionToml) {
  const auto dir = fresh_dir("tum");
  {
    auto w = create_ros1((dir / "a.bag").string());
    write_clouds(*w);
    w->close();
  }
  std::vector<io::PoseRecord> tum;
  for (double s : {0.0, 1.0, 2.0, 3.0}) tum.push_back({t0 + s, base_at(s) * kMount});
  io::write_poses((dir / "slam.txt").string(), tum);
  expect_error([&] { read(dir); }, "no poses for the clouds");
  std::ofstream(dir / "mission.toml") << "poses = \"slam.txt\"\n";
  BagMissionLog log;
  const Mission m = read(dir, {}, &log);
  EXPECT_EQ(log.pose_source, "slam.txt");
  ASSERT_EQ(m.scans.size(), 6u);
  expect_near(m.scans[5].pose, base_at(3) * kMount, "the TUM poses are the sensor's");
  expect_near(m.scans[2].pose, base_at(1) * kMount, "on a stamp");
}

TEST(BagMission, SeveralCloudTopicsNeedOneNamed) {
  const auto dir = fresh_dir("two_clouds");
  {
    auto w = create_ros1((dir / "a.bag").string());
    write_tf(*w);
    write_clouds(*w, "/front");
    write_clouds(*w, "/rear");
    w->close();
  }
  expect_error([&] { read(dir); }, "2 point cloud topics (/front, /rear); name one as cloud_topic");
  std::ofstream(dir / "mission.toml") << "cloud_topic = \"/rear\"\n";
  BagMissionLog log;
  read(dir, {}, &log);
  EXPECT_EQ(log.cloud_topic, "/rear");
  BagOptions wrong;
  wrong.cloud_topic = "/tf";
  std::filesystem::remove(dir / "mission.toml");
  expect_error([&] { read(dir, wrong); }, "cloud_topic /tf is a tf2_msgs/TFMessage, not a sensor_msgs/PointCloud2");
}

TEST(BagMission, BadInputIsOneLineNamingTheFileKeyOrFrame) {
  const auto dir = fresh_dir("bad");
  {
    auto w = create_ros1((dir / "a.bag").string());
    write_tf(*w);
    write_clouds(*w);
    w->close();
  }
  std::ofstream(dir / "mission.toml") << "# mine\ncloud_topc = \"/points\"\n";
  expect_error([&] { read(dir); }, "mission.toml:2: cloud_topc: unknown key");
  std::ofstream(dir / "mission.toml") << "fixed_frame = \"world\"\n";
  expect_error([&] { read(dir); }, "fixed_frame 'world' is not in /tf");
  std::ofstream(dir / "mission.toml") << "poses = \"/gps\"\n";
  expect_error([&] { read(dir); }, "poses '/gps' is neither tf, a topic of the bag");
  std::filesystem::remove(dir / "mission.toml");

  // A bag cut short: rosbag cannot read it, and the error names the file.
  const auto cut = fresh_dir("cut");
  const auto size = std::filesystem::file_size(dir / "a.bag");
  std::filesystem::copy_file(dir / "a.bag", cut / "a.bag");
  std::filesystem::resize_file(cut / "a.bag", size / 2);
  expect_error([&] { read(cut); }, (cut / "a.bag").string() + ": ");

  // Frames that never connect: the clouds' frame is in another tf tree.
  const auto apart = fresh_dir("apart");
  {
    auto w = create_ros1((apart / "a.bag").string());
    write_tf(*w);
    for (double s : {0.0, 1.0}) w->write_cloud("/points", cloud_at(t0 + s, "lidar", 0), t0 + s);
    w->write_tf("/tf", {{t0, "elsewhere", "camera", Eigen::Isometry3d::Identity()}}, t0);
    w->close();
  }
  BagOptions o;
  o.poses = "tf";
  o.fixed_frame = "elsewhere";
  expect_error([&] { read(apart, o); }, "tf: no transform from frame 'lidar' to 'elsewhere'");
}

namespace {

// A sweep of a wall at x = 5 taken in 0.1 s while the sensor turns 9 deg and
// moves 0.1 m: each point is given in the sensor frame of its own time, in a
// float32 "time" field (Velodyne's). The true wall points are returned.
std::vector<Eigen::Vector3d> write_skewed_sweep(Writer& w, double tf_step) {
  auto sensor_at = [](double tau) { return pose_xyz_yaw(0, tau, 0, 90 * tau); };
  for (double s = 0.0; s <= 0.2 + 1e-9; s += tf_step)
    w.write_tf("/tf", {{t0 + s, "map", "lidar", sensor_at(s)}}, t0 + s);
  Cloud c;
  c.stamp = t0, c.frame_id = "lidar", c.height = 1, c.width = 200, c.point_step = 16, c.row_step = 16 * 200;
  c.fields = {{"x", 0, float32, 1}, {"y", 4, float32, 1}, {"z", 8, float32, 1}, {"time", 12, float32, 1}};
  c.data.resize(c.row_step);
  std::vector<Eigen::Vector3d> wall;
  for (uint32_t k = 0; k < c.width; ++k) {
    const double tau = 0.1 * k / c.width;
    wall.emplace_back(5.0, -2.0 + 4.0 * k / c.width, 0.3);
    const Eigen::Vector3f p = (sensor_at(tau).inverse() * wall.back()).cast<float>();
    const float v[4] = {p.x(), p.y(), p.z(), float(tau)};
    std::memcpy(c.data.data() + 16 * k, v, 16);
  }
  w.write_cloud("/points", c, t0);
  return wall;
}

double worst_wall_error(const Mission& m, const std::vector<Eigen::Vector3d>& wall) {
  const PointSet& p = *m.scans.at(0).points;
  double worst = 0;
  for (size_t i = 0; i < p.size(); ++i)
    worst = std::max(worst, (m.scans[0].pose * p.xyz[i].cast<double>() - wall[p.index[i]]).norm());
  return worst;
}

}  // namespace

TEST(BagMission, DeskewsASweepByThePosesMotionWhenTheyAreDenseEnough) {
  const auto dir = fresh_dir("skew");
  std::vector<Eigen::Vector3d> wall;
  {
    auto w = create_ros1((dir / "a.bag").string());
    wall = write_skewed_sweep(*w, 0.05);
    w->close();
  }
  BagMissionLog log;
  const Mission m = read(dir, {}, &log);
  EXPECT_EQ(log.timed, 1u);
  EXPECT_EQ(log.deskewed, 1u);
  EXPECT_LT(worst_wall_error(m, wall), 1e-4) << "deskewed points lie on the wall";
  std::ofstream(dir / "mission.toml") << "deskew = false\n";
  const Mission raw = read(dir);
  EXPECT_GT(worst_wall_error(raw, wall), 0.5) << "the raw sweep is skewed: 9 deg at 5 m";

  // Poses 1 s apart cannot tell the motion within a 0.1 s sweep.
  const auto sparse = fresh_dir("skew_sparse");
  {
    auto w = create_ros1((sparse / "a.bag").string());
    write_skewed_sweep(*w, 0.2);
    w->close();
  }
  const Mission kept = read(sparse, {}, &log);
  EXPECT_EQ(log.deskewed, 0u);
  ASSERT_EQ(log.notes.size(), 1u);
  EXPECT_NE(log.notes[0].find("1 of 1 clouds with per-point times not deskewed: poses every 0.2 s"), std::string::npos)
      << log.notes[0];
}

TEST(BagMission, SeveralBagFilesAreReadAsOneRecording) {
  const auto dir = fresh_dir("split");
  {
    auto first = create_ros1((dir / "run_0.bag").string());
    write_tf(*first);
    for (double s : {0.0, 0.5}) first->write_cloud("/points", cloud_at(t0 + s, "lidar", float(s)), t0 + s);
    first->close();
    auto second = create_ros1((dir / "run_1.bag").string(), true);  // LZ4 chunks
    for (double s : {1.0, 1.5, 2.0}) second->write_cloud("/points", cloud_at(t0 + s, "lidar", float(s)), t0 + s);
    second->close();
  }
  BagMissionLog log;
  const Mission m = read(dir, {}, &log);
  EXPECT_NE(log.bag.find("run_0.bag (and 1 more)"), std::string::npos) << log.bag;
  ASSERT_EQ(m.scans.size(), 5u);
  expect_near(m.scans[4].pose, base_at(2) * kMount, "a cloud of the second file, placed by the first's tf");
  EXPECT_FLOAT_EQ(m.scans[3].points->xyz[0].x(), 1.5f);
}

// An index entry pointing inside an LZ4 chunk but not at one of its
// records (found by fuzz_ros1bag: rosbag parsed what it found there as a
// record header and read past the chunk's buffer, an ASan heap overflow)
// is an error naming the index: compressed chunks are decompressed and
// walked like plain ones before rosbag reads.
TEST(BagMission, AnIndexIntoAnLz4ChunkBetweenItsRecordsIsAnError) {
  const auto dir = fresh_dir("corrupt_lz4_index");
  fs::copy_file(fs::path(LISTA_ROS1BAG_CORPUS) / "lz4-index-offset.bag", dir / "a.bag");
  expect_error([&] { read(dir); }, "a.bag: the index at byte 7770 points outside its chunk's records: a corrupt bag");
}

// An index entry whose nanoseconds carry its time past 2^32 s (found by
// fuzz_ros1bag: ros::Time threw std::runtime_error through rosbag, which
// nothing turned into an error naming the file).
TEST(BagMission, AnIndexTimePastWhatRosCanHoldIsAnError) {
  const auto dir = fresh_dir("corrupt_index_time");
  fs::copy_file(fs::path(LISTA_ROS1BAG_CORPUS) / "index-time-overflow.bag", dir / "a.bag");
  expect_error([&] { read(dir); }, "a.bag: not a readable ROS 1 bag (Time is out of dual 32-bit range)");
}

// A record length past the file's end (found by fuzz_ros1bag: rosbag
// allocated the 2 GB it stated before finding it missing) is an error
// naming the byte, before rosbag reads anything.
TEST(BagMission, ALengthPastTheFilesEndIsAnErrorNotAnAllocation) {
  const auto dir = fresh_dir("corrupt_length");
  {
    auto w = create_ros1((dir / "a.bag").string());
    write_tf(*w);
    write_clouds(*w);
    w->close();
  }
  std::fstream f(dir / "a.bag", std::ios::in | std::ios::out | std::ios::binary);
  f.seekp(13);  // the bag header record's header length, after "#ROSBAG V2.0\n"
  const char huge[4] = {0, 0, 0, char(0x80)};
  f.write(huge, 4);
  f.close();
  expect_error([&] { read(dir); }, "a.bag: a record at byte 13 runs past the end of the file");
}
