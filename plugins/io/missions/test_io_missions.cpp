#include <lista_testing/plugin_stage.hpp>
#include <lista_io/test_scratch.hpp>

#include <gtest/gtest.h>
#include <lista/basic_context.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>

#include <Eigen/Geometry>
#include <filesystem>
#include <fstream>
#include <map>
#include <unistd.h>

using namespace lista;
namespace fs = std::filesystem;

namespace {

fs::path make_dataset(const std::string& tag) {
  const fs::path root = io::testing::scratch_path("io_missions_" + tag);
  for (const char* m : {"t1", "t0"}) {
    fs::create_directories(root / m / "scans");
    std::vector<io::PoseRecord> poses(2);
    for (int s = 0; s < 2; ++s) {
      PointSet p;
      for (int i = 0; i < 4; ++i) p.xyz.emplace_back(float(i) + 0.5f, float(s), 0.f);
      io::write_scan_pcd((root / m / "scans" / ("00" + std::to_string(s) + ".pcd")).string(), p);
      poses[s].timestamp = s;
    }
    io::write_poses((root / m / "poses.txt").string(), poses);
  }
  return root;
}

// Every message io.missions logs while reading the dataset at `root`.
std::string messages_reading(const fs::path& root) {
  BasicContext ctx;
  ctx.info.dataset = root.string();
  plugin_test::make_stage("io.missions")->run(Inputs{}, ctx);
  std::string all;
  for (const auto& m : ctx.messages) all += m + "\n";
  return all;
}

Eigen::Isometry3d poses_of_scan2() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(2, 0, 0);
  t.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

}  // namespace

TEST(IoMissions, ReadsTheRunDatasetSortedOrListed) {
  const fs::path root = make_dataset("a");
  BasicContext ctx("read", 2);
  ctx.info.dataset = root.string();
  auto all = plugin_test::make_stage("io.missions")->run(Inputs{}, ctx);
  const auto& set = all.at("missions").as<MissionSet>();
  ASSERT_EQ(set.missions.size(), 2u);
  EXPECT_EQ(set.missions[0].name, "t0");
  EXPECT_EQ(set.missions[1].point_count(), 8u);
  EXPECT_EQ(ctx.info.metrics["read"]["points"], 16.0);

  auto listed = plugin_test::make_stage("io.missions", {{"path", root.string()},
                                                     {"missions", std::vector<std::string>{"t1", "t0"}}})
                    ->run(Inputs{}, ctx);
  EXPECT_EQ(listed.at("missions").as<MissionSet>().missions[0].name, "t1");
}

TEST(IoMissions, PointsNearTheSensorAreDroppedKeepingFileIndices) {
  // Scan s holds points (i + 0.5, s, 0), i = 0..3: 1.2 m drops i = 0 of
  // scan 0 (0.5 m away) and of scan 1 (1.12 m), in both missions.
  const fs::path root = make_dataset("near");
  BasicContext ctx("read", 2);
  ctx.info.dataset = root.string();
  auto out = plugin_test::make_stage("io.missions", {{"min_range", 1.2}})->run(Inputs{}, ctx);
  const auto& m = out.at("missions").as<MissionSet>().missions[0];
  ASSERT_EQ(m.scans[0].points->size(), 3u);
  EXPECT_EQ(m.scans[0].points->index[0], 1u);
  EXPECT_EQ(m.scans[0].points->scan[0], 0u);
  EXPECT_FLOAT_EQ(m.scans[0].points->xyz[0].x(), 1.5f);
  ASSERT_EQ(m.scans[1].points->size(), 3u);
  EXPECT_EQ(m.scans[1].points->index[0], 1u);
  EXPECT_EQ(m.scans[1].points_in_file, 4u);
  EXPECT_EQ(ctx.info.metrics["read"]["dropped_near"], 4.0);
  EXPECT_EQ(ctx.info.metrics["read"]["points"], 12.0);
  // Everything inside the range: the mission is empty, and the error says why.
  try {
    plugin_test::make_stage("io.missions", {{"min_range", 5.0}})->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("farther than min_range"), std::string::npos) << e.what();
  }
}

// Many drivers write a missing return as (0, 0, 0) instead of NaN: such
// points are dropped, the others keep their file index.
TEST(IoMissions, PointsAtTheSensorOriginAreMissingReturns) {
  const fs::path root = make_dataset("zero");
  PointSet p;
  for (const float x : {0.f, 2.f, 0.f, 3.f}) p.xyz.emplace_back(x, 0.f, 0.f);
  io::write_scan_pcd((root / "t0" / "scans" / "001.pcd").string(), p);
  BasicContext ctx("read", 2);
  ctx.info.dataset = root.string();
  auto out = plugin_test::make_stage("io.missions")->run(Inputs{}, ctx);
  const auto& scan = out.at("missions").as<MissionSet>().missions[0].scans[1];
  ASSERT_EQ(scan.points->size(), 2u);
  EXPECT_EQ(scan.points->index, (std::vector<uint32_t>{1, 3}));
  EXPECT_EQ(scan.points_in_file, 4u);
  EXPECT_EQ(ctx.info.metrics["read"]["dropped_zero"], 2.0);
  EXPECT_EQ(ctx.info.metrics["read"]["dropped_near"], 0.0);
}

// Some exporters write a sweep twice (PCL's real room lists every point two
// or three times): a point repeating an earlier one of its scan to the bit
// is dropped, the first keeps its file index; -0 and +0 are one place, and
// the same point in another mission's scan is kept.
TEST(IoMissions, PointsRepeatedInTheirScanAreDroppedOnce) {
  const fs::path root = make_dataset("repeated");
  PointSet p;
  for (const Eigen::Vector3f& q : {Eigen::Vector3f(1, 2, 3), Eigen::Vector3f(4, 0, 0), Eigen::Vector3f(1, 2, 3),
                                   Eigen::Vector3f(1, 2, 3.0001f), Eigen::Vector3f(4, -0.0f, 0), Eigen::Vector3f(1, 2, 3)})
    p.xyz.push_back(q);
  io::write_scan_pcd((root / "t0" / "scans" / "001.pcd").string(), p);
  io::write_scan_pcd((root / "t1" / "scans" / "001.pcd").string(), p);
  BasicContext ctx("read", 2);
  ctx.info.dataset = root.string();
  auto out = plugin_test::make_stage("io.missions")->run(Inputs{}, ctx);
  for (const auto& mission : out.at("missions").as<MissionSet>().missions) {
    const auto& scan = mission.scans[1];
    ASSERT_EQ(scan.points->size(), 3u) << mission.name;
    EXPECT_EQ(scan.points->index, (std::vector<uint32_t>{0, 1, 3}));
  }
  EXPECT_EQ(ctx.info.metrics["read"]["dropped_repeated"], 6.0);
}

// A dense log read thinned: scans 0.5 m apart, one read per metre; the
// others are not called empty scans.
TEST(IoMissions, ScanSpacingThinsADenseLogWithoutCallingTheRestEmpty) {
  const fs::path root = io::testing::scratch_path("io_missions_dense");
  for (const char* m : {"A", "B"}) {
    fs::create_directories(root / m / "scans");
    std::vector<io::PoseRecord> poses(5);
    for (int s = 0; s < 5; ++s) {
      PointSet p;
      p.xyz.emplace_back(2.f, 0.f, 0.f);
      io::write_scan_pcd((root / m / "scans" / ("00" + std::to_string(s) + ".pcd")).string(), p);
      poses[s].timestamp = s;
      poses[s].pose.translation() = Eigen::Vector3d(0.5 * s, 0, 0);
    }
    io::write_poses((root / m / "poses.txt").string(), poses);
  }
  BasicContext ctx("read", 2);
  ctx.info.dataset = root.string();
  auto out = plugin_test::make_stage("io.missions", {{"scan_spacing", 1.0}})->run(Inputs{}, ctx);
  const auto& a = out.at("missions").as<MissionSet>().missions[0];
  ASSERT_EQ(a.scans.size(), 5u);
  EXPECT_EQ(a.point_count(), 3u);  // scans 0, 2 and 4
  EXPECT_TRUE(a.scans[1].points->empty());
  EXPECT_EQ(ctx.info.metrics["read"]["scans_read"], 6.0);
  EXPECT_EQ(ctx.info.metrics["read"]["scans"], 10.0);
  std::string all;
  for (const auto& msg : ctx.messages) all += msg + "\n";
  EXPECT_EQ(all.find("with no finite point"), std::string::npos) << all;
  EXPECT_NE(all.find("mission 'A': 5 scans (3 read, scan_spacing)"), std::string::npos) << all;
}

// A log of `scans` scans `step` metres apart along x, one point each.
fs::path make_log(const std::string& name, int scans, double step) {
  const fs::path root = io::testing::scratch_path(name);
  fs::create_directories(root / "A" / "scans");
  std::vector<io::PoseRecord> poses(static_cast<size_t>(scans));
  for (int s = 0; s < scans; ++s) {
    PointSet p;
    p.xyz.emplace_back(2.f, 0.f, 0.f);
    char file[32];
    std::snprintf(file, sizeof file, "%04d.pcd", s);
    io::write_scan_pcd((root / "A" / "scans" / file).string(), p);
    poses[size_t(s)].timestamp = s;
    poses[size_t(s)].pose.translation() = Eigen::Vector3d(step * s, 0, 0);
  }
  io::write_poses((root / "A" / "poses.txt").string(), poses);
  return root;
}

struct Read {
  size_t scans_read = 0;
  std::string messages;
};

Read read_log(const fs::path& root, const std::map<std::string, ParamValue>& params = {}) {
  BasicContext ctx("test", 2);
  ctx.info.dataset = root.string();
  auto out = plugin_test::make_stage("io.missions", params)->run(Inputs{}, ctx);
  Read r;
  for (const auto& scan : out.at("missions").as<MissionSet>().missions[0].scans) r.scans_read += !scan.points->empty();
  for (const auto& m : ctx.messages) r.messages += m + "\n";
  return r;
}

// A 10 Hz log (1000 scans 5 cm apart, 50 m) is read a scan every 0.5 m
// without being asked (dense_spacing), says so, and is read whole on request.
TEST(IoMissions, ADenseLogIsReadThinnedByDefault) {
  const fs::path root = make_log("io_missions_log", 1000, 0.05);
  const Read thinned = read_log(root);
  // Scans 0, 10, 20, ... (0.5 m each, within float rounding of the poses) and the last.
  EXPECT_GE(thinned.scans_read, 95u);
  EXPECT_LE(thinned.scans_read, 102u);
  EXPECT_NE(thinned.messages.find("mission 'A': a dense log (1000 scans, 0.05 m apart at the median): reading a scan "
                                  "every 0.5 m or 30 deg of turn (--set test.dense_spacing=0 reads every scan)"),
            std::string::npos)
      << thinned.messages;
  EXPECT_NE(thinned.messages.find("1000 scans (" + std::to_string(thinned.scans_read) + " read, dense_spacing)"),
            std::string::npos)
      << thinned.messages;
  const Read whole = read_log(root, {{"dense_spacing", 0.0}});
  EXPECT_EQ(whole.scans_read, 1000u);
  EXPECT_NE(whole.messages.find("read whole (dense_spacing = 0)"), std::string::npos) << whole.messages;
  // scan_spacing, when given, decides.
  EXPECT_EQ(read_log(root, {{"scan_spacing", 5.0}}).scans_read, 11u);
}

// Short logs, and logs of scans farther apart, are read whole: they cost
// little, and each scan there may be the only look at a place.
TEST(IoMissions, ShortOrSparseLogsAreReadWhole) {
  const Read short_log = read_log(make_log("io_missions_short", 400, 0.05));
  EXPECT_EQ(short_log.scans_read, 400u);
  EXPECT_EQ(short_log.messages.find("dense log"), std::string::npos) << short_log.messages;
  const Read sparse = read_log(make_log("io_missions_sparse", 600, 0.2));
  EXPECT_EQ(sparse.scans_read, 600u);
  EXPECT_EQ(sparse.messages.find("dense log"), std::string::npos) << sparse.messages;
}

TEST(IoMissions, ClearErrors) {
  const fs::path root = make_dataset("b");
  BasicContext ctx;
  try {
    plugin_test::make_stage("io.missions")->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no dataset"), std::string::npos) << e.what();
  }
  try {
    plugin_test::make_stage("io.missions", {{"path", root.string()}, {"missions", std::vector<std::string>{"t9"}}})
        ->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no mission 't9'"), std::string::npos) << e.what();
  }
}

// A mission folder whose poses.txt is missing (or misnamed) would drop out
// of the run without a word; it is an error naming it instead.
TEST(IoMissions, AMissionWithScansButNoPosesIsAnError) {
  const fs::path root = make_dataset("c");
  fs::rename(root / "t1" / "poses.txt", root / "t1" / "poses.csv");
  BasicContext ctx;
  ctx.info.dataset = root.string();
  try {
    plugin_test::make_stage("io.missions")->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t1: has scans/ but no poses.txt"), std::string::npos) << e.what();
  }
}

// scan_0 .. scan_11 without zero padding sort scan_10 before scan_2, and
// poses.txt pairs poses with scans in name order: a warning says so.
TEST(IoMissions, UnpaddedScanNumbersAreWarnedAbout) {
  const fs::path root = io::testing::scratch_path("io_missions_unpadded");
  for (const char* m : {"A", "B"}) {
    fs::create_directories(root / m / "scans");
    std::vector<io::PoseRecord> poses(12);
    for (int s = 0; s < 12; ++s) {
      PointSet p;
      p.xyz.emplace_back(1.f, float(s), 0.f);
      io::write_scan_pcd((root / m / "scans" / ("scan_" + std::to_string(s) + ".pcd")).string(), p);
      poses[s].timestamp = s;
    }
    io::write_poses((root / m / "poses.txt").string(), poses);
  }
  const std::string all = messages_reading(root);
  EXPECT_NE(all.find("mission 'A': scan_11.pcd sorts before scan_2.pcd by name"), std::string::npos) << all;

  const std::string padded = messages_reading(make_dataset("padded"));
  EXPECT_EQ(padded.find("sorts before"), std::string::npos) << padded;
}

// Missions week2, week9, week10 are compared in name order (the contract:
// week10, week2, week9) unless listed: a warning says how to list them;
// listed, or dated names whose orders agree, say nothing.
TEST(IoMissions, MissionNamesOutOfNumericOrderAreWarnedAbout) {
  const fs::path root = make_dataset("weeks");
  fs::rename(root / "t0", root / "week2");
  fs::copy(root / "week2", root / "week9", fs::copy_options::recursive);
  fs::rename(root / "t1", root / "week10");
  const std::string all = messages_reading(root);
  EXPECT_NE(all.find("mission week10 sorts before week2 by name"), std::string::npos) << all;
  EXPECT_NE(all.find(".missions=[...]"), std::string::npos) << all;

  BasicContext ctx;
  plugin_test::make_stage("io.missions", {{"path", root.string()},
                                      {"missions", std::vector<std::string>{"week2", "week9", "week10"}}})
      ->run(Inputs{}, ctx);
  for (const auto& m : ctx.messages) EXPECT_EQ(m.find("sorts before"), std::string::npos) << m;

  const fs::path dated = make_dataset("dated");
  fs::rename(dated / "t0", dated / "2026-05-30");
  fs::rename(dated / "t1", dated / "2026-06-02");
  EXPECT_EQ(messages_reading(dated).find("sorts before"), std::string::npos);
}

// A mission whose scans hold no finite point cannot be aligned or compared:
// one error naming it and the way to leave it out, not a pose error later.
TEST(IoMissions, AMissionWithNoPointsIsAnError) {
  const fs::path root = make_dataset("no_points");
  for (int s = 0; s < 2; ++s) {
    PointSet p;
    p.xyz.emplace_back(NAN, 0.f, 0.f);
    io::write_scan_pcd((root / "t1" / "scans" / ("00" + std::to_string(s) + ".pcd")).string(), p);
  }
  BasicContext ctx("load", 1);
  ctx.info.dataset = root.string();
  try {
    plugin_test::make_stage("io.missions")->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mission 't1': none of its 2 scans has a finite point off the sensor origin; leave it out with "
                                         "--set load.missions=[...]"),
              std::string::npos)
        << e.what();
  }
}

// Sensor-frame scans dropped into mission folders without poses.txt read
// as map-frame scans whose VIEWPOINT (PCL's default) is the identity.
TEST(IoMissions, ScansWithoutPosesAreWarnedAbout) {
  const fs::path root = io::testing::scratch_path("io_missions_no_poses");
  for (const char* m : {"A", "B"}) {
    fs::create_directories(root / m);
    for (int s = 0; s < 3; ++s) {
      PointSet p;
      p.xyz.emplace_back(1.f, float(s), 0.f);
      io::write_scan_pcd((root / m / ("00" + std::to_string(s) + ".pcd")).string(), p);
    }
  }
  const std::string all = messages_reading(root);
  EXPECT_NE(all.find("mission 'A': every scan's VIEWPOINT is the identity"), std::string::npos) << all;
}

// A scan with no finite point (a sensor dropout, a bad export) is named.
TEST(IoMissions, ScansWithoutPointsAreWarnedAbout) {
  const fs::path root = make_dataset("empty_scan");
  io::write_scan_pcd((root / "t0" / "scans" / "001.pcd").string(), PointSet{});
  const std::string all = messages_reading(root);
  EXPECT_NE(all.find("mission 't0': 1 scan with no finite point off the sensor origin (001.pcd)"), std::string::npos)
      << all;
  EXPECT_EQ(all.find("mission 't1': 1 scan"), std::string::npos) << all;
}

// One mission whose scans use every contract format (binary_compressed PCD,
// ASCII PLY, KITTI .bin) with KITTI poses: the stage reads all of them, keeps
// file indices across a skipped non-finite point and records the count.
TEST(IoMissions, EveryScanFormatInOneMission) {
  const fs::path root = io::testing::scratch_path("io_missions_formats");
  for (const char* m : {"A", "B"}) {
    const fs::path scans = root / m / "scans";
    fs::create_directories(scans);
    PointSet p;
    p.xyz = {{1.f, 2.f, 3.f}, {4.f, 5.f, 6.f}};
    p.intensity = {0.5f, 0.25f};
    p.label = {0u, 7u};
    io::write_scan_pcd((scans / "000.pcd").string(), p, io::PcdEncoding::binary_compressed);
    std::ofstream(scans / "001.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                        "property float z\nproperty uchar intensity\nend_header\n"
                                        "1 1 1 10\nnan 0 0 20\n2 2 2 30\n";
    const float bin[8] = {7.f, 8.f, 9.f, 0.1f, -1.f, -2.f, -3.f, 0.2f};
    std::ofstream(scans / "002.bin", std::ios::binary).write(reinterpret_cast<const char*>(bin), sizeof bin);
    std::vector<io::PoseRecord> poses(3);
    for (int s = 0; s < 3; ++s) poses[s].pose.translation() = Eigen::Vector3d(s, 0, 0);
    poses[2].pose.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    io::write_poses((root / m / "poses.txt").string(), poses, io::PoseFormat::kitti);
  }
  BasicContext ctx("read", 1);
  auto out = plugin_test::make_stage("io.missions", {{"path", root.string()}})->run(Inputs{}, ctx);
  const auto& set = out.at("missions").as<MissionSet>();
  ASSERT_EQ(set.missions.size(), 2u);
  const Mission& a = set.missions[0];
  ASSERT_EQ(a.scans.size(), 3u);
  EXPECT_EQ(a.skipped_nonfinite, 1u);
  EXPECT_EQ(a.point_count(), 6u);
  EXPECT_EQ(a.scans[0].points->label[1], 7u);
  EXPECT_FLOAT_EQ(a.scans[0].points->intensity[1], 0.25f);
  const PointSet& ply = *a.scans[1].points;
  ASSERT_EQ(ply.size(), 2u);
  EXPECT_EQ(a.scans[1].points_in_file, 3u);
  EXPECT_EQ(ply.index[1], 2u);  // the NaN row still counts
  EXPECT_EQ(ply.scan[1], 1u);
  EXPECT_FLOAT_EQ(ply.intensity[1], 30.f);
  const PointSet& kitti = *a.scans[2].points;
  ASSERT_EQ(kitti.size(), 2u);
  EXPECT_FLOAT_EQ(kitti.xyz[1].z(), -3.f);
  EXPECT_FLOAT_EQ(kitti.intensity[0], 0.1f);
  EXPECT_TRUE(a.scans[2].pose.isApprox(poses_of_scan2(), 1e-9));
  EXPECT_EQ(ctx.info.metrics["read"]["skipped_nonfinite"], 2.0);
  EXPECT_EQ(ctx.info.metrics["read"]["points"], 12.0);
}

TEST(IoMissions, ScanAndPoseCountsMustAgree) {
  const fs::path root = make_dataset("c");
  io::write_poses((root / "t0" / "poses.txt").string(), std::vector<io::PoseRecord>(3));
  BasicContext ctx;
  try {
    plugin_test::make_stage("io.missions", {{"path", root.string()}})->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("2 scan files in scans/ but 3 poses"), std::string::npos) << e.what();
  }
}

// One pose 10 000 km off the rest of its mission (a corrupt line) is said,
// not taken in silence; poses spread over a site are not.
TEST(IoMissions, APoseFarOffTheRestOfItsMissionIsWarnedAbout) {
  const fs::path root = io::testing::scratch_path("io_missions_far_pose");
  for (const char* m : {"A", "B"}) {
    fs::create_directories(root / m / "scans");
    std::vector<io::PoseRecord> poses(4);
    for (int s = 0; s < 4; ++s) {
      PointSet p;
      p.xyz.emplace_back(1.f, float(s), 0.f);
      io::write_scan_pcd((root / m / "scans" / ("00" + std::to_string(s) + ".pcd")).string(), p);
      poses[size_t(s)].timestamp = s;
      poses[size_t(s)].pose.translation() = Eigen::Vector3d(40.0 * s, 0, 0);  // a 120 m route
    }
    if (std::string(m) == "B") poses[2].pose.translation().x() = 1e7;
    io::write_poses((root / m / "poses.txt").string(), poses);
  }
  const std::string all = messages_reading(root);
  EXPECT_NE(all.find("mission 'B': 1 scan pose(s) lie far from the others"), std::string::npos) << all;
  EXPECT_NE(all.find("scan 2 (002.pcd) 1e+07 m"), std::string::npos) << all;
  EXPECT_EQ(all.find("mission 'A': 1 scan pose"), std::string::npos) << all;
}
