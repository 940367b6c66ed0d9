// lista-eval on a hand-made two-mission dataset: perfect run, empty run, a
// hand-computed run, and runs that break the contract.
#include "perfect_run.hpp"
#include "print.hpp"
#include "score.hpp"

#include <gtest/gtest.h>
#include <lista/error.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>
#include <lista_io/report.hpp>
#include <lista_io/test_scratch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <unistd.h>

using namespace lista;
namespace fs = std::filesystem;

namespace {

Eigen::Matrix4d translation(double x, double y, double z) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 1>(0, 3) = Eigen::Vector3d(x, y, z);
  return m;
}

// Writes mission `name` under `root`: one scan holding, per (label, n), n
// points of that label (~0u: non-finite), and its true pose `gt`.
void write_mission(const fs::path& root, const std::string& name, const std::vector<std::pair<uint32_t, int>>& runs,
                 const Eigen::Matrix4d& gt) {
  fs::create_directories(root / name / "scans");
  PointSet p;
  for (const auto& [label, n] : runs)
    for (int i = 0; i < n; ++i) {
      const float x = label == ~0u ? NAN : float(label) + 0.1f * float(i);
      p.xyz.emplace_back(x, 1.f, 0.f);
      p.intensity.push_back(1.f);
      p.label.push_back(label == ~0u ? 0 : label);
    }
  io::write_scan_pcd((root / name / "scans" / "000000.pcd").string(), p);
  io::PoseRecord r;
  io::write_poses((root / name / "poses.txt").string(), {r});
  r.pose.matrix() = gt;
  io::write_poses((root / name / "poses_gt.txt").string(), {r});
}

// Mission A: 10 structure, obj 1 (static) x4, obj 2 (removed) x4, obj 4 (moved) x4,
// obj 5 (dynamic) x2, one NaN point. Mission B: 10 structure, obj 1 x4, obj 3
// (added) x4, obj 4 x4. File order is the order listed; the NaN point is index 10.
struct Dataset {
  fs::path root;
  // index ranges (A): structure 0-9, NaN 10, obj1 11-14, obj2 15-18, obj4 19-22, obj5 23-24
  // (B): structure 0-9, obj1 10-13, obj3 14-17, obj4 18-21
  Dataset() {
    root = io::testing::scratch_path("eval_ds");
    write_mission(root, "A", {{0, 10}, {~0u, 1}, {1, 4}, {2, 4}, {4, 4}, {5, 2}}, Eigen::Matrix4d::Identity());
    write_mission(root, "B", {{0, 10}, {1, 4}, {3, 4}, {4, 4}}, translation(0, 0.3, 0));
    io::GroundTruth g;
    g.missions = {"A", "B"};
    g.mission_to_world = {{"A", Eigen::Matrix4d::Identity()}, {"B", Eigen::Matrix4d::Identity()}};
    auto obj = [&](int id, const char* cls, bool dyn, std::optional<Eigen::Matrix4d> a, std::optional<Eigen::Matrix4d> b) {
      io::TruthObject o;
      o.id = id;
      o.class_name = cls;
      o.dynamic = dyn;
      o.poses = {{"A", a}, {"B", b}};
      g.objects.push_back(o);
    };
    const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
    obj(1, "chair", false, I, translation(0.01, 0, 0));  // 1 cm: static
    obj(2, "box", false, I, std::nullopt);
    obj(3, "box", false, std::nullopt, I);
    obj(4, "cart", false, I, translation(1, 0, 0));
    obj(5, "person", true, I, std::nullopt);
    io::write_ground_truth((root / "ground_truth.json").string(), g);
  }
};

const Dataset& dataset() {
  static Dataset d;
  return d;
}

fs::path run_dir(const std::string& tag) {
  const fs::path d = io::testing::scratch_path("eval_run_" + tag);
  fs::create_directories(d / "changes");
  return d;
}

// A change cloud: rows of (index, object) in scan 0.
void write_changes(const fs::path& run, const std::string& mission, const std::vector<std::pair<uint32_t, int>>& rows) {
  std::vector<float> x(rows.size(), 0.f);
  std::vector<uint32_t> scan(rows.size(), 0), index;
  std::vector<int32_t> object;
  for (const auto& [i, o] : rows) {
    index.push_back(i);
    object.push_back(o);
  }
  io::write_pcd((run / "changes" / (mission + ".pcd")).string(), rows.size(),
                {{"x", 'F', x.data()}, {"y", 'F', x.data()}, {"z", 'F', x.data()}, {"scan", 'U', scan.data()},
                 {"index", 'U', index.data()}, {"object", 'I', object.data()}});
}

std::vector<std::pair<uint32_t, int>> range(uint32_t from, uint32_t to, int object) {
  std::vector<std::pair<uint32_t, int>> v;
  for (uint32_t i = from; i <= to; ++i) v.emplace_back(i, object);
  return v;
}

template <class... V>
std::vector<std::pair<uint32_t, int>> rows(V... parts) {
  std::vector<std::pair<uint32_t, int>> out;
  (out.insert(out.end(), parts.begin(), parts.end()), ...);
  return out;
}

io::ReportObject robj(int id, const std::string& m, const std::string& status, int match = -1,
                      std::optional<Eigen::Matrix4d> t = std::nullopt) {
  io::ReportObject o;
  o.id = id;
  o.mission = m;
  o.status = status;
  o.match = match;
  o.transform = t;
  o.confidence = 0.5;
  return o;
}

io::Report empty_report() {
  io::Report r;
  r.missions = {"A", "B"};
  r.alignment = {{"A", Eigen::Matrix4d::Identity()}, {"B", Eigen::Matrix4d::Identity()}};
  return r;
}

eval::Truth truth() { return eval::load_truth(dataset().root.string(), {"A", "B"}, 2); }

// Runs the lista-eval program; returns its exit status and stderr.
std::pair<int, std::string> run_tool(const std::string& args) {
  const std::string err = io::testing::scratch_path("eval_err").string();
  const int rc = std::system((std::string(LISTA_BIN_DIR) + "/lista-eval " + args + " >/dev/null 2>" + err).c_str());
  std::ifstream in(err);
  std::stringstream ss;
  ss << in.rdbuf();
  return {WEXITSTATUS(rc), ss.str()};
}

}  // namespace

TEST(Eval, TruthStatusesFollowTheContract) {
  const eval::Truth t = truth();
  EXPECT_EQ(t.changed, (std::set<uint32_t>{2, 3, 4}));
  EXPECT_EQ(t.dynamic, (std::set<uint32_t>{5}));
  EXPECT_EQ(t.status.at(2).at("A"), "removed");
  EXPECT_EQ(t.status.at(3).at("B"), "added");
  EXPECT_EQ(t.status.at(4).at("B"), "moved");
  EXPECT_FALSE(t.status.count(1));
  EXPECT_EQ(t.labels[0].labels[0][10], eval::kNoPoint);
}

// Three missions: an object moved A->B and gone in C is in B moved and
// removed at once, one that arrived in B and moved in C is added and moved;
// a report may give either. One that stood still A->B and moved B->C
// changed against A only through C: its one status is the sequence's.
// The three-mission dataset below; its sensors stand at (0,0,0), (1,0,0)
// and (0,2,0) (poses_gt.txt).
fs::path write_three_missions() {
  const fs::path root = io::testing::scratch_path("eval_ds3");
  const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
  write_mission(root, "A", {{0, 10}, {6, 4}, {8, 4}}, I);
  write_mission(root, "B", {{0, 10}, {6, 4}, {7, 4}, {8, 4}}, translation(1, 0, 0));
  write_mission(root, "C", {{0, 10}, {7, 4}, {8, 4}}, translation(0, 2, 0));
  io::GroundTruth g;
  g.missions = {"A", "B", "C"};
  g.mission_to_world = {{"A", I}, {"B", I}, {"C", I}};
  auto obj = [&](int id, std::optional<Eigen::Matrix4d> a, std::optional<Eigen::Matrix4d> b,
                 std::optional<Eigen::Matrix4d> c) {
    io::TruthObject o;
    o.id = id;
    o.class_name = "box";
    o.poses = {{"A", a}, {"B", b}, {"C", c}};
    g.objects.push_back(o);
  };
  obj(6, I, translation(1, 0, 0), std::nullopt);
  obj(7, std::nullopt, I, translation(0, 1, 0));
  obj(8, I, I, translation(0, 0.5, 0));
  io::write_ground_truth((root / "ground_truth.json").string(), g);
  return root;
}

TEST(Eval, WithThreeMissionsEveryStatusOfANeighbouringChangeIsRight) {
  const fs::path root = write_three_missions();
  const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
  const eval::Truth t = eval::load_truth(root.string(), {}, 1);
  using S = std::set<std::string>;
  EXPECT_EQ(t.accepted.at(6).at("A"), S{"moved"});
  EXPECT_EQ(t.accepted.at(6).at("B"), (S{"moved", "removed"}));
  EXPECT_EQ(t.accepted.at(7).at("B"), (S{"added", "moved"}));
  EXPECT_EQ(t.accepted.at(7).at("C"), S{"moved"});
  EXPECT_EQ(t.accepted.at(8).at("A"), S{"moved"}) << "only through C";
  EXPECT_EQ(t.status.at(6).at("B"), "moved");

  // A run that calls B's object 6 removed and B's object 7 added has every
  // status right; a perfect run from the truth too, with every move matched.
  const fs::path run = run_dir("three");
  write_changes(run, "A", {});
  write_changes(run, "B", rows(range(10, 13, 0), range(14, 17, 1)));
  write_changes(run, "C", {});
  io::Report r;
  r.missions = {"A", "B", "C"};
  r.alignment = {{"A", I}, {"B", I}, {"C", I}};
  r.objects = {robj(0, "B", "removed"), robj(1, "B", "added")};
  io::write_report((run / "report.json").string(), r);
  const eval::Score sc = eval::score_run(t, run.string());
  const eval::ObjectScore& b = sc.objects.at(1);
  EXPECT_EQ(b.paired, 2u);
  EXPECT_EQ(b.status_correct, 2u);
  // Of B's moves only object 8's (not reported) counts: 6 and 7 rightly
  // got their other status, which is no missed match.
  EXPECT_EQ(b.moved, 1u);
  EXPECT_EQ(b.moved_matched, 0u);

  const fs::path perfect = io::testing::scratch_path("eval_perfect3");
  eval::write_perfect_run(t, perfect.string());
  const eval::Score ps = eval::score_run(t, perfect.string());
  const eval::ObjectScore& all = ps.objects.back();
  ASSERT_FALSE(ps.alignment.empty());
  EXPECT_NEAR(ps.alignment.back().scan_ate_rmse_m, 0.0, 1e-9) << "every scan at its true pose (poses/)";
  EXPECT_EQ(all.status_correct, all.paired);
  EXPECT_EQ(all.moved_matched, all.moved);
  EXPECT_GT(all.moved, 0u);
}

// poses/<mission>.txt (io.report) hold every scan as the run placed it:
// their ATE after one rigid fit is 0 for the true positions moved as a
// whole, grows with an error in one scan, and is undefined without poses/.
TEST(Eval, TheRunsScanPosesAreScoredAfterOneRigidFit) {
  const fs::path root = write_three_missions();
  const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
  const eval::Truth t = eval::load_truth(root.string(), {}, 1);
  const fs::path run = run_dir("scan_poses");
  io::Report r;
  r.missions = {"A", "B", "C"};
  r.alignment = {{"A", I}, {"B", I}, {"C", I}};
  io::write_report((run / "report.json").string(), r);
  for (const char* m : {"A", "B", "C"}) write_changes(run, m, {});
  auto score_with = [&](double error_in_c) {
    fs::create_directories(run / "poses");
    const std::map<std::string, Eigen::Vector3d> at{{"A", {0, 0, 0}}, {"B", {1, 0, 0}}, {"C", {0, 2 + error_in_c, 0}}};
    for (const auto& [m, p] : at) {
      io::PoseRecord rec;
      rec.pose.translation() = p + Eigen::Vector3d(10, -4, 1);  // the run's own common frame
      io::write_poses((run / "poses" / (m + ".txt")).string(), {rec});
    }
    return eval::score_run(t, run.string()).alignment;
  };
  const auto exact = score_with(0.0);
  ASSERT_EQ(exact.back().mission, "all");
  EXPECT_NEAR(exact.back().scan_ate_rmse_m, 0.0, 1e-9);
  EXPECT_GT(score_with(0.3).back().scan_ate_rmse_m, 0.05);
  fs::remove_all(run / "poses");
  EXPECT_TRUE(std::isnan(eval::score_run(t, run.string()).alignment.back().scan_ate_rmse_m));
}

TEST(Eval, PerfectRunScoresOneEverywhere) {
  const eval::Truth t = truth();
  const fs::path run = run_dir("perfect");
  eval::write_perfect_run(t, run.string());
  const eval::Score s = eval::score_run(t, run.string());
  EXPECT_EQ(s.points.fp, 0u);
  EXPECT_EQ(s.points.fn, 0u);
  EXPECT_EQ(s.points.tp, 16u);
  EXPECT_EQ(s.points.tn, 28u);
  for (double v : {s.points.precision(), s.points.recall(), s.points.specificity(), s.points.f1(), s.points.iou()})
    EXPECT_DOUBLE_EQ(v, 1.0);
  const eval::ObjectScore& all = s.objects.back();
  EXPECT_EQ(all.mission, "all");
  EXPECT_EQ(all.true_changed, 4u);
  for (double v : {all.precision(), all.recall(), all.status_accuracy(), all.match_accuracy()}) EXPECT_DOUBLE_EQ(v, 1.0);
  ASSERT_EQ(all.translation_error_m.size(), 2u);
  EXPECT_NEAR(eval::median(all.translation_error_m), 0.0, 1e-9);
  EXPECT_NEAR(eval::median(all.rotation_error_deg), 0.0, 1e-6);
  // B's poses.txt is 0.3 m off its poses_gt.txt: ATE shows exactly that.
  ASSERT_EQ(s.alignment.size(), 3u);
  EXPECT_NEAR(s.alignment[0].ate_rmse_m, 0.0, 1e-12);
  EXPECT_NEAR(s.alignment[1].ate_rmse_m, 0.3, 1e-12);
  EXPECT_NEAR(s.alignment[2].ate_rmse_m, std::sqrt(0.09 / 2), 1e-12);
}

TEST(Eval, EmptyRunHasRecallZero) {
  const fs::path run = run_dir("empty");
  io::write_report((run / "report.json").string(), empty_report());
  write_changes(run, "A", {});
  write_changes(run, "B", {});
  const eval::Score s = eval::score_run(truth(), run.string());
  EXPECT_EQ(s.points.recall(), 0.0);
  EXPECT_TRUE(std::isnan(s.points.precision()));
  EXPECT_EQ(s.points.specificity(), 1.0);
  EXPECT_EQ(s.objects.back().recall(), 0.0);
  EXPECT_TRUE(std::isnan(s.objects.back().precision()));
}

TEST(Eval, HandComputedCase) {
  const fs::path run = run_dir("hand");
  io::Report r = empty_report();
  const Eigen::Vector3d c(5, 1, 0);
  // id 2's transform: the true inverse move after a 10 degree turn about c.
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
  turn.translate(c).rotate(Eigen::AngleAxisd(10 * M_PI / 180, Eigen::Vector3d::UnitZ())).translate(-c);
  r.objects = {robj(0, "A", "removed"), robj(1, "A", "moved", 2, translation(1.1, 0, 0)),
               robj(2, "B", "moved", 1, translation(-1, 0, 0) * turn.matrix()), robj(3, "B", "added"),
               robj(4, "B", "added")};
  r.objects[2].centroid = c;
  io::write_report((run / "report.json").string(), r);
  // A: obj2 -> id 0; obj4 + 1 structure -> id 1 (IoU 0.8); a dynamic point with -1.
  write_changes(run, "A", rows(range(15, 18, 0), range(19, 22, 1), range(0, 0, 1), range(23, 23, -1)));
  // B: obj4 -> id 2; static obj1 -> id 3; 3 of obj3 + 2 structure -> id 4 (IoU exactly 0.5: no pair).
  write_changes(run, "B", rows(range(18, 21, 2), range(10, 13, 3), range(14, 16, 4), range(1, 2, 4)));
  const eval::Score s = eval::score_run(truth(), run.string());
  EXPECT_EQ(s.points.tp, 15u);
  EXPECT_EQ(s.points.fp, 7u);
  EXPECT_EQ(s.points.tn, 21u);
  EXPECT_EQ(s.points.fn, 1u);
  EXPECT_DOUBLE_EQ(s.points.precision(), 15.0 / 22);
  EXPECT_DOUBLE_EQ(s.points.recall(), 15.0 / 16);
  EXPECT_DOUBLE_EQ(s.points.specificity(), 0.75);
  EXPECT_DOUBLE_EQ(s.points.f1(), 30.0 / 38);
  EXPECT_DOUBLE_EQ(s.points.iou(), 15.0 / 23);
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_EQ(s.objects[0].paired, 2u);
  EXPECT_EQ(s.objects[1].reported, 3u);
  EXPECT_EQ(s.objects[1].paired, 1u);
  const eval::ObjectScore& all = s.objects[2];
  EXPECT_DOUBLE_EQ(all.precision(), 3.0 / 5);
  EXPECT_DOUBLE_EQ(all.recall(), 3.0 / 4);
  EXPECT_DOUBLE_EQ(all.status_accuracy(), 1.0);
  EXPECT_DOUBLE_EQ(all.match_accuracy(), 1.0);
  EXPECT_NEAR(eval::median(all.translation_error_m), 0.05, 1e-9);
  EXPECT_NEAR(eval::mean(all.rotation_error_deg), 5.0, 1e-9);
  EXPECT_NEAR(eval::median(all.rotation_error_deg), 5.0, 1e-9);
  // Per object: A's 2 and 4 and B's 4 right; B's 3 only at IoU 0.5, missed.
  ASSERT_EQ(s.verdicts.size(), 4u);
  const std::vector<std::tuple<std::string, uint32_t, int, std::string>> want{
      {"A", 2, 0, "ok"}, {"A", 4, 1, "ok"}, {"B", 3, -1, "missed"}, {"B", 4, 2, "ok"}};
  for (size_t k = 0; k < want.size(); ++k) {
    const auto& [m, id, rep, verdict] = want[k];
    EXPECT_EQ(s.verdicts[k].mission, m);
    EXPECT_EQ(s.verdicts[k].truth_id, id);
    EXPECT_EQ(s.verdicts[k].report_id, rep);
    EXPECT_EQ(s.verdicts[k].verdict, verdict);
  }
  EXPECT_EQ(s.verdicts[1].class_name, "cart");
  EXPECT_EQ(s.verdicts[1].truth_points, 4u);
  EXPECT_DOUBLE_EQ(s.verdicts[1].iou, 0.8);
  EXPECT_EQ(s.verdicts[1].expected_match, 2);
  EXPECT_NEAR(s.verdicts[3].rotation_error_deg, 10.0, 1e-9);  // B's obj4: report 2, the 10 degree turn
  EXPECT_TRUE(std::isnan(s.verdicts[0].rotation_error_deg));  // removed: no motion
  const std::string table = eval::format_table(s, true);
  EXPECT_NE(table.find("missed"), std::string::npos);
  EXPECT_EQ(eval::format_table(s).find("missed"), std::string::npos);
  EXPECT_NE(eval::format_json(s).find("\"object_verdicts\""), std::string::npos);
}

// A half-turned transform is "pose off"; with the true pose among the
// report's alternative_transforms it is "pose listed", and the counts say so.
TEST(Eval, HalfTurnWithTheTruthAmongTheAlternativesIsPoseListed) {
  const fs::path run = run_dir("listed");
  io::Report r = empty_report();
  auto half_turn_about = [](const Eigen::Vector3d& c) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.translate(c).rotate(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ())).translate(-c);
    return t.matrix();
  };
  const Eigen::Vector3d ca(4, 1, 0), cb(5, 1, 0);
  r.objects = {robj(0, "A", "removed"), robj(1, "A", "moved", 2, translation(1, 0, 0) * half_turn_about(ca)),
               robj(2, "B", "moved", 1, translation(-1, 0, 0) * half_turn_about(cb)), robj(3, "B", "added"),
               robj(4, "B", "added")};
  r.objects[1].centroid = ca;
  r.objects[2].centroid = cb;
  r.objects[2].alternative_transforms = {translation(-1, 0, 0)};  // the truth, listed
  io::write_report((run / "report.json").string(), r);
  write_changes(run, "A", rows(range(15, 18, 0), range(19, 22, 1)));
  write_changes(run, "B", rows(range(18, 21, 2), range(10, 13, 3)));
  const eval::Score s = eval::score_run(truth(), run.string());
  ASSERT_EQ(s.verdicts.size(), 4u);
  EXPECT_EQ(s.verdicts[1].verdict, "pose off");     // A obj4: turned, nothing listed
  EXPECT_EQ(s.verdicts[1].alternatives, 0u);
  EXPECT_EQ(s.verdicts[3].verdict, "pose listed");  // B obj4: turned, the truth listed
  EXPECT_EQ(s.verdicts[3].alternatives, 1u);
  EXPECT_NEAR(s.verdicts[3].rotation_error_deg, 180.0, 1e-6);  // the medians score `transform` only
  const eval::ObjectScore& all = s.objects.back();
  EXPECT_EQ(all.ambiguous, 1u);
  EXPECT_EQ(all.pose_off, 2u);
  EXPECT_EQ(all.pose_off_listed, 1u);
  EXPECT_NE(eval::format_table(s).find("1 of 2 flagged ambiguous"), std::string::npos);
  EXPECT_NE(eval::format_json(s).find("\"pose_off_listed\": 1"), std::string::npos);
}

TEST(Eval, VerdictsNameWrongStatusAndWrongMatch) {
  const fs::path run = run_dir("verdicts");
  io::Report r = empty_report();
  // Removed obj2 called moved; moved obj4 matched in both missions to the
  // wrong report (3 is the static obj1, 0 is obj2).
  const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
  r.objects = {robj(0, "A", "moved", 3, I), robj(1, "A", "moved", 3, I), robj(2, "B", "moved", 0, I),
               robj(3, "B", "moved", 1, I)};
  io::write_report((run / "report.json").string(), r);
  write_changes(run, "A", rows(range(15, 18, 0), range(19, 22, 1)));
  write_changes(run, "B", rows(range(18, 21, 2), range(10, 13, 3)));
  const eval::Score s = eval::score_run(truth(), run.string());
  ASSERT_EQ(s.verdicts.size(), 4u);
  EXPECT_EQ(s.verdicts[0].verdict, "status");  // A obj2
  EXPECT_EQ(s.verdicts[1].verdict, "match");   // A obj4 -> 3
  EXPECT_EQ(s.verdicts[1].report_match, 3);
  EXPECT_EQ(s.verdicts[1].expected_match, 2);
  EXPECT_TRUE(std::isnan(s.verdicts[1].rotation_error_deg));  // wrong match: no motion error
  EXPECT_EQ(s.verdicts[2].verdict, "missed");  // B obj3: no report
  EXPECT_EQ(s.verdicts[3].verdict, "match");   // B obj4 -> 0
  EXPECT_EQ(s.objects.back().match_accuracy(), 0.0);
}

// A run that compared B before A (names sorted otherwise than recorded)
// is scored in its own order, with a warning naming both orders.
TEST(Eval, ARunInAnotherMissionOrderThanTheTruthsIsWarnedAbout) {
  const std::string ds = dataset().root.string();
  const fs::path run = run_dir("reversed");
  io::Report r = empty_report();
  r.missions = {"B", "A"};
  io::write_report((run / "report.json").string(), r);
  write_changes(run, "A", {});
  write_changes(run, "B", {});
  const auto [rc, err] = run_tool("--dataset " + ds + " --run " + run.string());
  EXPECT_EQ(rc, 0) << err;
  EXPECT_NE(err.find("warning: the run compared the missions in the order B, A, ground_truth.json lists them as A, B"),
            std::string::npos)
      << err;
  io::write_report((run / "report.json").string(), empty_report());
  EXPECT_EQ(run_tool("--dataset " + ds + " --run " + run.string()).second.find("order"), std::string::npos);
}

TEST(Eval, ContractBreaksGiveOneLineErrorsAndNonZeroExit) {
  const std::string ds = dataset().root.string();
  const fs::path run = run_dir("broken");
  auto expect_fail = [&](const std::string& needle) {
    const auto [rc, err] = run_tool("--dataset " + ds + " --run " + run.string());
    EXPECT_NE(rc, 0);
    EXPECT_NE(err.find(needle), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  };
  expect_fail("report.json: missing");
  io::write_report((run / "report.json").string(), empty_report());
  write_changes(run, "A", {});
  expect_fail("changes/B.pcd: missing");
  write_changes(run, "B", {{99, -1}});
  expect_fail("row 0: scan 0 index 99 is not a finite point of mission 'B'");
  write_changes(run, "B", {{10, 7}});
  expect_fail("object 7 is not an object of mission 'B'");
  write_changes(run, "B", {});
  {
    std::ofstream(run / "report.json") << R"({"format":"lista-report/1","missions":["A","B"],"alignment":{}})";
  }
  expect_fail("alignment: no entry for mission 'A'");
  io::Report r = empty_report();
  r.missions = {"A", "C"};
  r.alignment = {{"A", Eigen::Matrix4d::Identity()}, {"C", Eigen::Matrix4d::Identity()}};
  io::write_report((run / "report.json").string(), r);
  expect_fail("mission 'C' is not in");
  // Wrong fields: a bad status word, a float 'object' column, another format.
  {
    std::ofstream(run / "report.json")
        << R"({"format":"lista-report/1","missions":["A","B"],"alignment":{"A":[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]],)"
        << R"("B":[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]},"objects":[{"id":1,"mission":"A","status":"gone",)"
        << R"("centroid":[0,0,0],"bbox_min":[0,0,0],"bbox_max":[0,0,0],"points":1,"group":0,"confidence":1,"match":null}],)"
        << R"("timings_s":{}})";
  }
  expect_fail("status: is 'gone', expected moved, removed or added");
  io::write_report((run / "report.json").string(), empty_report());
  {
    const float v[1] = {0.f};
    const uint32_t u[1] = {10u};
    io::write_pcd((run / "changes" / "B.pcd").string(), 1,
                  {{"x", 'F', v}, {"y", 'F', v}, {"z", 'F', v}, {"scan", 'U', v}, {"index", 'U', u}, {"object", 'F', v}});
  }
  expect_fail("scan and index must be uint32 (U), object int32 (I)");
  write_changes(run, "B", {});
  {
    std::ofstream(run / "report.json") << R"({"format":"lista-report/2","missions":["A","B"]})";
  }
  expect_fail("expected 'lista-report/1'");
  // The tool itself: a good run scores with exit 0; --truth writes a loadable run.
  const fs::path perfect = run_dir("tool_perfect");
  EXPECT_EQ(run_tool("--dataset " + ds + " --truth " + perfect.string()).first, 0);
  EXPECT_EQ(run_tool("--dataset " + ds + " --run " + perfect.string() + " --json").first, 0);
  EXPECT_NE(run_tool("--dataset " + ds).first, 0);
}

// Two chairs exchange places (6 and 7), a third chair moves elsewhere (8),
// and a box moves onto where chair 8 stood (9, another class): only 6 and 7
// are a swap. Their missed points are counted apart and the recall without
// them is given; the other missed points still count.
TEST(Eval, ObjectsThatExchangedPlacesAreCountedApart) {
  const fs::path root = io::testing::scratch_path("eval_swap");
  // A and B: structure 0-3, chair 6 at 4-7, chair 7 at 8-11, chair 8 at 12-15, box 9 at 16-19.
  write_mission(root, "A", {{0, 4}, {6, 4}, {7, 4}, {8, 4}, {9, 4}}, Eigen::Matrix4d::Identity());
  write_mission(root, "B", {{0, 4}, {6, 4}, {7, 4}, {8, 4}, {9, 4}}, Eigen::Matrix4d::Identity());
  io::GroundTruth g;
  g.missions = {"A", "B"};
  g.mission_to_world = {{"A", Eigen::Matrix4d::Identity()}, {"B", Eigen::Matrix4d::Identity()}};
  auto obj = [&](int id, const char* cls, const Eigen::Matrix4d& a, const Eigen::Matrix4d& b) {
    io::TruthObject o;
    o.id = id;
    o.class_name = cls;
    o.poses = {{"A", a}, {"B", b}};
    g.objects.push_back(o);
  };
  obj(6, "chair", translation(0, 0, 0), translation(3, 0, 0.05));  // within kSwapMeters of 7's place
  obj(7, "chair", translation(3, 0, 0), translation(0, 0.1, 0));
  obj(8, "chair", translation(6, 0, 0), translation(9, 0, 0));
  obj(9, "box", translation(12, 0, 0), translation(6, 0, 0));
  io::write_ground_truth((root / "ground_truth.json").string(), g);
  const eval::Truth t = eval::load_truth(root.string(), {"A", "B"}, 1);
  EXPECT_EQ(t.swapped.at("A"), (std::set<uint32_t>{6, 7}));
  EXPECT_EQ(t.swapped.at("B"), (std::set<uint32_t>{6, 7}));

  // The run finds chair 8 and the box in both missions, nothing of the swap.
  const fs::path run = run_dir("swap");
  io::Report r = empty_report();
  r.objects = {robj(0, "A", "moved", 2, translation(3, 0, 0)), robj(1, "A", "moved", 3, translation(-6, 0, 0)),
               robj(2, "B", "moved", 0, translation(-3, 0, 0)), robj(3, "B", "moved", 1, translation(6, 0, 0))};
  io::write_report((run / "report.json").string(), r);
  write_changes(run, "A", rows(range(12, 15, 0), range(16, 19, 1)));
  write_changes(run, "B", rows(range(12, 15, 2), range(16, 18, 3)));  // one box point missed
  const eval::Score s = eval::score_run(t, run.string());
  EXPECT_EQ(s.points.fn, 17u);
  EXPECT_EQ(s.points.swapped, 16u);
  EXPECT_EQ(s.points.fn_swapped, 16u);
  EXPECT_DOUBLE_EQ(s.points.recall(), 15.0 / 32);
  EXPECT_DOUBLE_EQ(s.points.recall_without_swaps(), 15.0 / 16);
  size_t swapped_verdicts = 0;
  for (const auto& v : s.verdicts) {
    swapped_verdicts += v.swapped;
    EXPECT_EQ(v.swapped, v.truth_id == 6 || v.truth_id == 7) << v.truth_id;
  }
  EXPECT_EQ(swapped_verdicts, 4u);
  EXPECT_NE(eval::format_table(s, true).find("swaps: 16 FN points"), std::string::npos);
  EXPECT_NE(eval::format_table(s, true).find("missed (swap)"), std::string::npos);
}
