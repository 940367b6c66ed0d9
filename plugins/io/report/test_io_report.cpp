#include <lista_testing/plugin_stage.hpp>
#include <lista_io/test_scratch.hpp>

#include <algorithm>

#include <gtest/gtest.h>
#include <lista/basic_context.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>
#include <lista_io/report.hpp>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

using namespace lista;
namespace fs = std::filesystem;

namespace {

fs::path out_dir(const std::string& tag) {
  const fs::path d = io::testing::scratch_path("io_report_" + tag);
  return d;
}

Object make_object(int id, uint32_t mission, float x0, uint32_t scan, uint32_t first_index, int n) {
  Object o;
  o.id = id;
  o.mission = mission;
  for (int i = 0; i < n; ++i) {
    o.points.xyz.emplace_back(x0 + 0.1f * i, 1.f, 2.f);
    o.points.scan.push_back(scan);
    o.points.index.push_back(first_index + uint32_t(i));
  }
  o.update_geometry();
  return o;
}

struct Fixture {
  MissionSet missions;
  ObjectSet objects;
  Matches matches;
  MissionPoints changes;
  Fixture() {
    for (const char* n : {"A", "B"}) {
      Mission m;
      m.name = n;
      missions.missions.push_back(m);
    }
    missions.missions[1].to_common.translation() = Eigen::Vector3d(1, 2, 3);
    for (int i = 0; i < 2; ++i) {  // B's scans, as an aligner left them
      Scan s;
      s.timestamp = 5.0 + i;
      s.pose.translation() = Eigen::Vector3d(1.0 + i, 0, 0);
      missions.missions[1].scans.push_back(s);
    }
    objects.missions = {"A", "B"};
    objects.objects = {make_object(0, 0, 0.f, 0, 10, 4), make_object(1, 1, 5.f, 2, 0, 4),
                       make_object(2, 1, 9.f, 3, 7, 2)};
    objects.objects[0].floor_z = -0.25f;  // measured by a stage; the others unknown
    ObjectChange a{0, ChangeStatus::moved, 1, 0.1, 0.9, true, Eigen::Matrix4d::Identity(), {0, 1}, {}};
    a.transform(0, 3) = 5;
    Eigen::Matrix4d half_turn = a.transform;  // a symmetric shape's twin pose
    half_turn.block<3, 3>(0, 0) = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    a.alternative_transforms = {half_turn};
    ObjectChange b{1, ChangeStatus::moved, 0, 0.1, 0.9, false, Eigen::Matrix4d::Identity(), {0, 1}, {}};
    ObjectChange c{2, ChangeStatus::added, -1, 0, 0.7, false, Eigen::Matrix4d::Identity(), {2}, {}};
    matches.objects = {a, b, c};
    changes.missions = {"A", "B"};
    changes.sets.resize(2);
    // One change point that is also in object 0 (written once, as object 0), one in no object.
    for (uint32_t idx : {10u, 99u}) {
      changes.sets[0].xyz.emplace_back(0.f, 0.f, 0.f);
      changes.sets[0].scan.push_back(0);
      changes.sets[0].index.push_back(idx);
    }
  }
  Inputs inputs(bool with_matches = true, bool with_changes = true) const {
    Inputs in;
    in.set("missions", Data::make(missions));
    in.set("objects", Data::make(objects));
    if (with_matches) in.set("matches", Data::make(matches));
    if (with_changes) in.set("changes", Data::make(changes));
    return in;
  }
};

}  // namespace

TEST(IoReport, WritesTheContractAndReadsBack) {
  Fixture f;
  const fs::path out = out_dir("full");
  BasicContext ctx("report");
  ctx.info.output_dir = out.string();
  ctx.info.seed = 42;
  ctx.info.finished = {{"read", "io.missions", 1.5, 100 << 20}, {"diff", "volumetric.octomap", 2.0, 200 << 20}};
  ctx.info.plugins = {{"io.missions", "1.0.0", "liblista_io_missions.so"}};
  ctx.info.dataset = "/data/exp1";
  ctx.info.threads = 8;
  ctx.info.jobs = 2;
  ctx.info.notes["describe"]["weights"] = "/models/describe-learned.bin";
  plugin_test::make_stage("io.report")->run(f.inputs(), ctx);

  const io::Report r = io::read_report((out / "report.json").string());
  EXPECT_EQ(r.missions, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(r.alignment.at("B")(1, 3), 2.0);
  ASSERT_EQ(r.objects.size(), 3u);
  EXPECT_EQ(r.objects[0].status, "moved");
  EXPECT_EQ(r.objects[0].match, 1);
  EXPECT_EQ((*r.objects[0].transform)(0, 3), 5.0);
  // Object 1 had no transform: the centroid translation back to object 0.
  EXPECT_NEAR((*r.objects[1].transform)(0, 3), -5.0, 1e-5);
  // The log's line for the move says the pose is ambiguous.
  EXPECT_TRUE(std::any_of(ctx.messages.begin(), ctx.messages.end(), [](const std::string& m) {
    return m.find("moved 0 (A) -> 1 (B)") != std::string::npos &&
           m.find("pose ambiguous (1 other fits as well)") != std::string::npos;
  })) << "no move line saying the pose is ambiguous";
  ASSERT_EQ(r.objects[0].alternative_transforms.size(), 1u);  // passed on, in the common frame
  EXPECT_NEAR(r.objects[0].alternative_transforms[0](0, 0), -1.0, 1e-12);
  EXPECT_TRUE(r.objects[1].alternative_transforms.empty());
  EXPECT_EQ(r.objects[2].status, "added");
  EXPECT_EQ(r.objects[2].match, -1);
  EXPECT_EQ(r.objects[2].group, -1);
  EXPECT_EQ(r.objects[1].points, 4u);
  EXPECT_NEAR(r.objects[0].bbox_max.x(), 0.3, 1e-6);
  ASSERT_TRUE(r.objects[0].floor_z.has_value());  // the object's floor, passed through
  EXPECT_DOUBLE_EQ(*r.objects[0].floor_z, -0.25);
  EXPECT_FALSE(r.objects[1].floor_z.has_value());
  ASSERT_EQ(r.timings_s.size(), 2u);
  EXPECT_EQ(r.timings_s[1].first, "diff");
  const auto extra = nlohmann::json::parse(r.extra_json);
  EXPECT_EQ(extra["provenance"]["seed"], 42);
  EXPECT_EQ(extra["provenance"]["plugins"][0]["name"], "io.missions");
  EXPECT_EQ(extra["provenance"]["stages"][1]["peak_rss_mib"], 200.0);
  // What a run depended on beyond its parameters, for tracing it later.
  EXPECT_EQ(extra["provenance"]["dataset"], "/data/exp1");
  EXPECT_EQ(extra["provenance"]["threads"], 8);
  EXPECT_EQ(extra["provenance"]["jobs"], 2);
  EXPECT_EQ(extra["provenance"]["notes"]["describe"]["weights"], "/models/describe-learned.bin");

  const io::PcdTable a = io::read_pcd_table((out / "changes" / "A.pcd").string());
  ASSERT_EQ(a.size, 5u);  // 4 object points + 1 change point in no object
  EXPECT_EQ(a.names, (std::vector<std::string>{"x", "y", "z", "scan", "index", "object"}));
  EXPECT_EQ(a.types, (std::vector<char>{'F', 'F', 'F', 'U', 'U', 'I'}));
  EXPECT_EQ(a.values[5][0], 0.0);
  EXPECT_EQ(a.values[4][4], 99.0);
  EXPECT_EQ(a.values[5][4], -1.0);
  const io::PcdTable b = io::read_pcd_table((out / "changes" / "B.pcd").string());
  EXPECT_EQ(b.size, 6u);
  // poses/<mission>.txt: every scan's sensor pose in the common frame, as
  // the run placed it, with its timestamp.
  const std::vector<io::PoseRecord> poses_b = io::read_poses((out / "poses" / "B.txt").string());
  ASSERT_EQ(poses_b.size(), 2u);
  EXPECT_EQ(poses_b[1].timestamp, 6.0);
  EXPECT_TRUE(poses_b[1].pose.translation().isApprox(Eigen::Vector3d(3, 2, 3))) << poses_b[1].pose.translation();
  EXPECT_TRUE(fs::exists(out / "poses" / "A.txt"));
  // Nothing temporary is left behind.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_TRUE(e.path().filename() == "report.json" || e.path().filename() == "changes" ||
                e.path().filename() == "poses")
        << e.path();
}

// An earlier run with a mission C left changes/C.pcd: a run over A and B
// must not leave it there looking like its own.
TEST(IoReport, ChangeCloudsOfMissionsNotInTheRunAreRemoved) {
  Fixture f;
  const fs::path out = out_dir("stale");
  fs::create_directories(out / "changes");
  std::ofstream(out / "changes" / "C.pcd") << "old";
  std::ofstream(out / "changes" / "notes.txt") << "the user's own";
  fs::create_directories(out / "poses");
  std::ofstream(out / "poses" / "C.txt") << "0 0 0 0 0 0 0 1\n";
  BasicContext ctx("report");
  ctx.info.output_dir = out.string();
  plugin_test::make_stage("io.report")->run(f.inputs(), ctx);
  EXPECT_TRUE(fs::exists(out / "changes" / "A.pcd"));
  EXPECT_TRUE(fs::exists(out / "changes" / "B.pcd"));
  EXPECT_FALSE(fs::exists(out / "changes" / "C.pcd"));
  EXPECT_FALSE(fs::exists(out / "poses" / "C.txt"));
  EXPECT_TRUE(fs::exists(out / "poses" / "B.txt"));
  EXPECT_TRUE(fs::exists(out / "changes" / "notes.txt"));
}

// A run killed while writing (SIGKILL) leaves its hidden temp folder: the
// next run into the folder removes it, but not one whose process still runs.
TEST(IoReport, TempFoldersOfDeadRunsAreCleared) {
  Fixture f;
  const fs::path out = out_dir("killed");
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  ASSERT_GT(dead, 0);
  waitpid(dead, nullptr, 0);
  const fs::path left = out / (".lista-report.tmp." + std::to_string(dead));
  const fs::path running = out / (".lista-report.tmp." + std::to_string(getppid()));
  fs::create_directories(left / "changes");
  fs::create_directories(running);
  BasicContext ctx("report");
  ctx.info.output_dir = out.string();
  plugin_test::make_stage("io.report")->run(f.inputs(), ctx);
  EXPECT_FALSE(fs::exists(left));
  EXPECT_TRUE(fs::exists(running)) << "a live run's temp folder is not ours to remove";
  EXPECT_TRUE(fs::exists(out / "report.json"));
}

TEST(IoReport, WithoutMatchesStatusFollowsMissionOrder) {
  Fixture f;
  const fs::path out = out_dir("nomatch");
  BasicContext ctx;
  plugin_test::make_stage("io.report", {{"path", out.string()}})->run(f.inputs(false, false), ctx);
  const io::Report r = io::read_report((out / "report.json").string());
  EXPECT_EQ(r.objects[0].status, "removed");
  EXPECT_EQ(r.objects[1].status, "added");
  EXPECT_EQ(io::read_pcd_table((out / "changes" / "A.pcd").string()).size, 4u);
}

TEST(IoReport, FailuresLeaveNoReport) {
  Fixture f;
  BasicContext ctx;
  try {
    plugin_test::make_stage("io.report")->run(f.inputs(), ctx);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no output folder"), std::string::npos);
  }
  const fs::path out = out_dir("fail");
  fs::create_directories(out);
  std::ofstream(out / "report.json") << "{}";  // a stale report from an earlier run
  f.changes.missions = {"A", "Z"};
  try {
    plugin_test::make_stage("io.report", {{"path", out.string()}})->run(f.inputs(), ctx);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mission 'Z'"), std::string::npos) << e.what();
  }
  f.changes.missions = {"A", "B"};
  // Writing fails: "changes" is a file, so the change clouds cannot be moved in.
  std::ofstream(out / "changes") << "x";
  EXPECT_THROW(plugin_test::make_stage("io.report", {{"path", out.string()}})->run(f.inputs(), ctx), Error);
  EXPECT_FALSE(fs::exists(out / "report.json"));
  size_t entries = 0;
  for (auto& e : fs::directory_iterator(out)) (void)e, ++entries;
  EXPECT_EQ(entries, 1u);  // only the "changes" file: the temp folder is gone
}

// Runs the report with B's scan 0 left unread (no points, points_in_file
// 0) and stored in `file`; returns changes/B.pcd.
static io::PcdTable changes_of_b_with_scan_0_unread(Fixture& f, const fs::path& file, const fs::path& run, BasicContext& ctx) {
  f.missions.missions[1].scans[0].file = file.string();
  f.missions.missions[1].scans[0].points = std::make_shared<const PointSet>();
  ctx.info.output_dir = run.string();
  plugin_test::make_stage("io.report")->run(f.inputs(), ctx);
  return io::read_pcd_table((run / "changes" / "B.pcd").string());
}

// A scan io.missions did not read (scan_spacing) is read here: its points
// that fall in a change cell join changes/ with that cell's object, under
// their own scan and file index; the rest, and missing returns, do not.
TEST(IoReport, PointsOfUnreadScansInChangedCellsAreReported) {
  Fixture f;
  const fs::path out = out_dir("unread");
  fs::create_directories(out);
  // B's scan 0 sits at (1, 0, 0) in B's map, which lies at (1, 2, 3): its
  // sensor sees object 1's first points (5..5.3, 1, 2) at (3..3.3, -1, -1).
  PointSet scan;
  scan.xyz = {{3.02f, -1.f, -1.f}, {8.f, 8.f, 8.f}, {0.f, 0.f, 0.f}, {3.15f, -1.f, -1.f}};
  const fs::path file = out / "unread-scan.pcd";
  io::write_scan_pcd(file.string(), scan);
  BasicContext ctx("report");
  const io::PcdTable b = changes_of_b_with_scan_0_unread(f, file, out / "run", ctx);
  ASSERT_EQ(b.size, 8u);  // the 6 of the fixture and 2 of the unread scan
  std::vector<std::pair<double, double>> from_unread;  // (index, object) of rows of scan 0
  for (size_t i = 0; i < b.size; ++i)
    if (b.values[3][i] == 0.0) from_unread.emplace_back(b.values[4][i], b.values[5][i]);
  EXPECT_EQ(from_unread, (std::vector<std::pair<double, double>>{{0.0, 1.0}, {3.0, 1.0}}));
  EXPECT_EQ(ctx.info.metrics["report"]["unread_scans"], 1.0);
  EXPECT_EQ(ctx.info.metrics["report"]["unread_points_changed"], 2.0);
}

// The same in the VIEWPOINT layout (a mission folder without poses.txt):
// the unread scan's points are in the map frame, its pose in VIEWPOINT.
TEST(IoReport, UnreadScansOfTheViewpointLayoutAreReadInTheMapFrame) {
  Fixture f;
  const fs::path out = out_dir("unread_viewpoint");
  fs::create_directories(out / "B");
  // B's map lies at (1, 2, 3) in the common frame: object 1's first point
  // (5, 1, 2) is at (4, -1, -1) in B's map; the scan's sensor at (1, 0, 0).
  std::vector<float> x = {4.02f, 9.f}, y = {-1.f, 9.f}, z = {-1.f, 9.f};
  Eigen::Isometry3d viewpoint = Eigen::Isometry3d::Identity();
  viewpoint.translation() = Eigen::Vector3d(1, 0, 0);
  const fs::path file = out / "B" / "000.pcd";
  io::write_pcd(file.string(), 2, {{"x", 'F', x.data()}, {"y", 'F', y.data()}, {"z", 'F', z.data()}},
                io::PcdEncoding::binary, viewpoint);
  f.missions.missions[1].dir = (out / "B").string();
  BasicContext ctx("report");
  const io::PcdTable b = changes_of_b_with_scan_0_unread(f, file, out / "run", ctx);
  ASSERT_EQ(b.size, 7u);  // the 6 of the fixture and the one point on object 1
  EXPECT_EQ(b.values[3][6], 0.0);
  EXPECT_EQ(b.values[4][6], 0.0);
  EXPECT_EQ(b.values[5][6], 1.0);
  EXPECT_NEAR(b.values[0][6], 5.02, 1e-4);
}

// What moved during a mission is listed apart from the objects, where it
// was in the dataset's coordinates, and counted in the log.
TEST(IoReport, ListsDynamicsApartFromTheObjects) {
  Fixture f;
  f.missions.origin = Eigen::Vector3d(1000, 0, 0);
  Dynamic d;
  d.mission = 1;
  d.points = 321;
  d.centroid = Eigen::Vector3f(2, 3, 1);
  d.bbox_min = Eigen::Vector3f(1.8f, 2.8f, 0);
  d.bbox_max = Eigen::Vector3f(2.2f, 3.2f, 1.8f);
  f.objects.dynamics = {d};
  const fs::path out = out_dir("dynamics");
  BasicContext ctx("report");
  ctx.min_level = LogLevel::error;
  ctx.info.output_dir = out.string();
  plugin_test::make_stage("io.report")->run(f.inputs(), ctx);
  std::ifstream in(out / "report.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("dynamics").size(), 1u);
  EXPECT_EQ(j["dynamics"][0]["mission"], "B");
  EXPECT_EQ(j["dynamics"][0]["points"], 321);
  EXPECT_DOUBLE_EQ(j["dynamics"][0]["centroid"][0].get<double>(), 1002.0);
  EXPECT_NEAR(j["dynamics"][0]["bbox_max"][2].get<double>(), 1.8, 1e-6);
  EXPECT_EQ(j.at("objects").size(), 3u);
  EXPECT_TRUE(std::any_of(ctx.messages.begin(), ctx.messages.end(), [](const std::string& m) {
    return m.find("dynamics 1: moved during their own mission") != std::string::npos;
  }));
  fs::remove_all(out);
}
