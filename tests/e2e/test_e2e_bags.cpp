// The same simulated scene written as PCD folders, as ROS 1 bags and as ROS 2
// bags (.db3 and .mcap) gives the same report, with the poses from /tf, from
// the odometry topic and from the TUM file beside the bag; lista-eval scores
// the bag dataset as it scores the folders.
#include "e2e_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>

using nlohmann::json;

namespace {

class BagScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new e2e::TempDir("bags");
    folders_ = run_on("pcd", "");
  }
  static void TearDownTestSuite() { delete dir_; }

  // Simulates the tiny scene as `format` (once per format) and runs the
  // default pipeline on it with `set` (e.g. "--set load.poses=/odom").
  static std::string run_on(const std::string& format, const std::string& set) {
    const std::string data = (dir_->path() / ("data-" + format)).string();
    if (!std::filesystem::exists(data)) {
      const auto sim = e2e::simulate("--preset tiny --seed 1 --format " + format, data);
      EXPECT_EQ(sim.status, 0) << sim.output;
    }
    const std::string out = (dir_->path() / ("out-" + format + "-" + std::to_string(runs_++))).string();
    last_run_ = e2e::run(e2e::bin("lista-run") + " " + e2e::source("pipelines/lista.toml") + " --dataset " + data +
                         " --out " + out + " --threads 2 " + set + " 2>&1");
    EXPECT_EQ(last_run_.status, 0) << last_run_.output;
    return out;
  }

  // Objects, statuses and matches identical; centroids and transforms within
  // 1e-9 (the same numbers).
  static void expect_same_report(const std::string& out, const std::string& what, double metres = 1e-9, double degrees = 1e-9) {
    SCOPED_TRACE(what);
    const json a = json::parse(e2e::read_file(folders_ + "/report.json"));
    const json b = json::parse(e2e::read_file(out + "/report.json"));
    ASSERT_EQ(b.at("objects").size(), a.at("objects").size());
    ASSERT_GT(a.at("objects").size(), 0u);
    for (size_t i = 0; i < a.at("objects").size(); ++i) {
      const json &x = a.at("objects")[i], &y = b.at("objects")[i];
      SCOPED_TRACE(x.dump());
      EXPECT_EQ(y.at("status"), x.at("status"));
      EXPECT_EQ(y.at("match"), x.at("match"));
      EXPECT_EQ(y.at("mission"), x.at("mission"));
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(y.at("centroid")[k].get<double>(), x.at("centroid")[k].get<double>(), metres);
      if (x.contains("transform") && x.at("transform").is_array()) {
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(y.at("transform")[r][c].get<double>(), x.at("transform")[r][c].get<double>(), degrees * M_PI / 180);
          EXPECT_NEAR(y.at("transform")[r][3].get<double>(), x.at("transform")[r][3].get<double>(), metres);
        }
      }
    }
  }

  static e2e::TempDir* dir_;
  static std::string folders_;
  static int runs_;
  static e2e::Result last_run_;
};

e2e::TempDir* BagScene::dir_ = nullptr;
std::string BagScene::folders_;
int BagScene::runs_ = 0;
e2e::Result BagScene::last_run_;

}  // namespace

// Through /tf, /odom or the TUM file the bag's clouds get poses.txt's
// numbers bit for bit (lista-sim mounts the LiDAR at the base's origin, and
// a cloud on a pose sample's stamp takes the sample itself), so the bag run
// gives the folders' report exactly.
TEST_F(BagScene, Ros1BagsGiveTheFoldersReportWithPosesFromTfOdometryOrTum) {
  auto strip = [](json r) {
    r.erase("timings_s");
    r.erase("provenance");
    return r;
  };
  const json folders = strip(json::parse(e2e::read_file(folders_ + "/report.json")));
  const std::string tum = run_on("bag", "--set load.poses=trajectory.txt");
  EXPECT_EQ(strip(json::parse(e2e::read_file(tum + "/report.json"))), folders) << "TUM file";
  const std::string odom = run_on("bag", "--set load.poses=/odom");
  EXPECT_NE(last_run_.output.find("poses from /odom"), std::string::npos) << last_run_.output;
  EXPECT_EQ(strip(json::parse(e2e::read_file(odom + "/report.json"))), folders) << "odometry";
  // One dataset may mix the two: a bag mission beside a folder mission.
  const std::filesystem::path mixed = dir_->path() / "data-mixed";
  std::filesystem::create_directories(mixed);
  std::filesystem::copy(dir_->path() / "data-bag" / "A", mixed / "A", std::filesystem::copy_options::recursive);
  std::filesystem::copy(dir_->path() / "data-pcd" / "B", mixed / "B", std::filesystem::copy_options::recursive);
  std::filesystem::copy(dir_->path() / "data-pcd" / "ground_truth.json", mixed / "ground_truth.json");
  const std::string mixed_out = (dir_->path() / "out-mixed").string();
  const auto r = e2e::run(e2e::bin("lista-run") + " " + e2e::source("pipelines/lista.toml") + " --dataset " + mixed.string() +
                          " --out " + mixed_out + " --threads 2 --set load.poses=trajectory.txt 2>&1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(strip(json::parse(e2e::read_file(mixed_out + "/report.json"))),
            strip(json::parse(e2e::read_file(folders_ + "/report.json"))));

  const std::string tf = run_on("bag", "");
  EXPECT_NE(last_run_.output.find("clouds on /points, poses from tf (map -> lidar)"), std::string::npos) << last_run_.output;
  EXPECT_EQ(strip(json::parse(e2e::read_file(tf + "/report.json"))), folders) << "tf";

  // lista-eval reads the bag missions for the per-point truth: same scores.
  const auto score = [](const std::string& data, const std::string& run) {
    const auto r = e2e::run(e2e::bin("lista-eval") + " --dataset " + data + " --run " + run + " --json 2>&1");
    EXPECT_EQ(r.status, 0) << r.output;
    return json::parse(r.output);
  };
  const json a = score((dir_->path() / "data-pcd").string(), folders_);
  const json b = score((dir_->path() / "data-bag").string(), tf);
  EXPECT_EQ(b.at("points"), a.at("points"));
}

// The reading benchmark on the same missions: every cloud counted, the
// thinning of io.missions, time and memory printed.
TEST_F(BagScene, TheReadingBenchmarkReadsBagsAsIoMissionsDoes) {
  run_on("bag", "");
  const auto r = e2e::run(e2e::bin("lista-bench") + " bagread " + (dir_->path() / "data-bag" / "A").string() + " 2>&1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("mission.bag)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("scans       10, 10 read"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("peak RSS"), std::string::npos) << r.output;
}

TEST_F(BagScene, Ros2BagsInSqliteAndMcapGiveTheFoldersReport) {
  expect_same_report(run_on("ros2", ""), "ROS 2, .db3, tf");
  expect_same_report(run_on("mcap", "--set load.poses=/odom"), "ROS 2, .mcap, /odom");
  expect_same_report(run_on("mcap", ""), "ROS 2, .mcap, tf");
}

TEST_F(BagScene, ABagMissionWithoutUsablePosesIsAOneLineErrorAndNoReport) {
  const std::string data = (dir_->path() / "data-bag").string();
  run_on("bag", "");  // makes the dataset when this test runs alone
  const std::string out = (dir_->path() / "out-bad").string();
  const auto r = e2e::run(e2e::bin("lista-run") + " " + e2e::source("pipelines/lista.toml") + " --dataset " + data +
                          " --out " + out + " --threads 2 --set load.poses=/nowhere 2>&1");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("poses '/nowhere' is neither tf, a topic of the bag (/odom (nav_msgs/Odometry), /points"),
            std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out + "/report.json"));
}

// A sensor turning at 90 deg/s during its 0.1 s sweeps (lista-sim --skew
// --spin 90): read as the driver gives them the scans are skewed by 9 deg and
// the missions cannot be aligned; deskewed by their per-point times they are.
TEST(SkewedBag, SweepsAreDeskewedByTheirPointTimesAndAlignAgain) {
  e2e::TempDir dir("skew");
  const std::string data = (dir.path() / "data").string();
  const auto sim = e2e::simulate("--preset tiny --seed 1 --skew --spin 90 --format bag", data);
  ASSERT_EQ(sim.status, 0) << sim.output;
  auto ate_after = [&](const std::string& set) {
    const std::string out = (dir.path() / ("out" + set.substr(set.size() - 4))).string();
    const auto r = e2e::run(e2e::bin("lista-run") + " " + e2e::source("pipelines/lista.toml") + " --dataset " + data +
                            " --out " + out + " --threads 2 " + set + " 2>&1");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_EQ(r.output.find("not deskewed"), std::string::npos) << r.output;
    return json::parse(e2e::read_file(out + "/report.json")).at("metrics").at("align").at("ate_after_m").get<double>();
  };
  const double deskewed = ate_after("--set load.deskew=true"), raw = ate_after("--set load.deskew=false");
  EXPECT_LT(deskewed, 0.05);
  EXPECT_GT(raw, 10 * deskewed);
}
