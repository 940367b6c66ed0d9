// lista-sim and lista-eval together: the perfect run of a generated `tiny`
// dataset scores 1 everywhere, an empty run has recall 0, and the ATE of the
// true alignment is the odometry drift (non-zero, small).
#include <lista_io/report.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/test_scratch.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;
using namespace lista;

namespace {

const fs::path& root() {
  static const fs::path r = [] {
    const fs::path p = io::testing::scratch_path("sim_eval");
    fs::create_directories(p);
    return p;
  }();
  return r;
}

int run(const std::string& program, const std::string& args, const fs::path& stdout_file) {
  const std::string cmd =
      std::string(LISTA_BIN_DIR) + "/" + program + " " + args + " > " + stdout_file.string() + " 2>&1";
  return WEXITSTATUS(std::system(cmd.c_str()));
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

const fs::path& tiny() {
  static const fs::path d = [] {
    const fs::path out = root() / "tiny";
    EXPECT_EQ(run("lista-sim", "--preset tiny --seed 3 --threads 2 --out " + out.string(), root() / "sim.log"), 0);
    return out;
  }();
  return d;
}

}  // namespace

TEST(SimEval, PerfectRunScoresOneAndShowsTheDrift) {
  const fs::path perfect = root() / "perfect";
  ASSERT_EQ(run("lista-eval", "--dataset " + tiny().string() + " --truth " + perfect.string(), root() / "t.log"), 0);
  const fs::path json = root() / "perfect.json";
  ASSERT_EQ(run("lista-eval", "--dataset " + tiny().string() + " --run " + perfect.string() + " --json", json), 0);
  const nlohmann::json s = read_json(json);
  for (const char* k : {"precision", "recall", "specificity", "f1", "iou"}) EXPECT_EQ(s["points"][k], 1.0) << k;
  EXPECT_GT(s["points"]["tp"].get<double>(), 0);
  const auto& all = s["objects"].back();
  EXPECT_EQ(all["mission"], "all");
  for (const char* k : {"precision", "recall", "status_accuracy", "match_accuracy"}) EXPECT_EQ(all[k], 1.0) << k;
  EXPECT_GE(all["moved"].get<int>(), 2);  // tiny moves objects in every later mission
  EXPECT_LT(all["translation_error_m"]["median"].get<double>(), 1e-6);
  const auto& ate = s["alignment"].back();
  EXPECT_EQ(ate["mission"], "all");
  EXPECT_GT(ate["ate_rmse_m"].get<double>(), 0.0);  // drift: poses.txt is not poses_gt.txt
  EXPECT_LT(ate["ate_rmse_m"].get<double>(), 0.5);
}

TEST(SimEval, EmptyRunHasRecallZero) {
  const fs::path perfect = root() / "empty";
  ASSERT_EQ(run("lista-eval", "--dataset " + tiny().string() + " --truth " + perfect.string(), root() / "t.log"), 0);
  // Keep the report's missions and alignment, drop every object and change point.
  io::Report r = io::read_report((perfect / "report.json").string());
  r.objects.clear();
  io::write_report((perfect / "report.json").string(), r);
  for (const auto& m : r.missions) io::write_pcd((perfect / "changes" / (m + ".pcd")).string(), 0,
                                                 {{"x", 'F', nullptr}, {"y", 'F', nullptr}, {"z", 'F', nullptr},
                                                  {"scan", 'U', nullptr}, {"index", 'U', nullptr},
                                                  {"object", 'I', nullptr}});
  const fs::path json = root() / "empty.json";
  ASSERT_EQ(run("lista-eval", "--dataset " + tiny().string() + " --run " + perfect.string() + " --json", json), 0);
  const nlohmann::json s = read_json(json);
  EXPECT_EQ(s["points"]["recall"], 0.0);
  EXPECT_EQ(s["points"]["tp"], 0);
  EXPECT_EQ(s["objects"].back()["recall"], 0.0);
}

// The confidence AUC: the perfect run has no wrong report (no AUC); one
// report given a wrong status is wrong, and the AUC says whether the
// confidences rank it below the right ones (1), above them (0) or alike (0.5).
TEST(SimEval, ConfidenceAucRanksWrongReportsAgainstRightOnes) {
  const fs::path run_dir = root() / "confidence";
  ASSERT_EQ(run("lista-eval", "--dataset " + tiny().string() + " --truth " + run_dir.string(), root() / "t.log"), 0);
  auto score = [&](const char* name) {
    const fs::path json = root() / name;
    EXPECT_EQ(run("lista-eval", "--dataset " + tiny().string() + " --run " + run_dir.string() + " --json", json), 0);
    return read_json(json)["confidence"];
  };
  const auto perfect = score("c0.json");
  EXPECT_EQ(perfect["wrong"], 0);
  EXPECT_TRUE(perfect["auc"].is_null()) << "no wrong report to rank";
  io::Report r = io::read_report((run_dir / "report.json").string());
  auto removed = std::find_if(r.objects.begin(), r.objects.end(), [](const io::ReportObject& o) { return o.status == "removed"; });
  ASSERT_NE(removed, r.objects.end());
  removed->status = "added";  // the wrong status: a wrong report
  for (auto& o : r.objects) o.confidence = &o == &*removed ? 0.1 : 0.9;
  io::write_report((run_dir / "report.json").string(), r);
  const auto below = score("c1.json");
  EXPECT_EQ(below["wrong"], 1);
  EXPECT_EQ(below["right"].get<size_t>(), r.objects.size() - 1);
  EXPECT_DOUBLE_EQ(below["auc"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(below["auc_removed_added"].get<double>(), 1.0);
  EXPECT_TRUE(below["auc_moved"].is_null()) << "every move is right";
  removed->confidence = 0.95;
  io::write_report((run_dir / "report.json").string(), r);
  EXPECT_DOUBLE_EQ(score("c2.json")["auc"].get<double>(), 0.0);
  removed->confidence = 0.9;
  io::write_report((run_dir / "report.json").string(), r);
  EXPECT_DOUBLE_EQ(score("c3.json")["auc"].get<double>(), 0.5);
}
