// lista-bench registration as a user runs it: both GICPs on the same pairs,
// one table row per sensor and method, every pair converged and near the
// truth (the numbers are measured by the program, not asserted as times);
// and on a recorded dataset's scan pairs, scored against its poses_gt.txt.
#include "e2e_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream s(row);
  std::string cell;
  std::getline(s, cell, '|');  // before the first bar
  while (std::getline(s, cell, '|')) {
    const size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
    if (a != std::string::npos) out.push_back(cell.substr(a, b - a + 1));
  }
  return out;
}

}  // namespace

TEST(BenchRegistration, BothMethodsOnEverySensorConvergeNearTheTruth) {
  const auto r = e2e::run(e2e::bin("lista-bench-registration") + " --pairs 3 --seed 2 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.output;
  std::stringstream lines(r.output);
  std::string line;
  int rows = 0;
  while (std::getline(lines, line)) {
    const auto c = cells(line);
    if (c.size() != 8 || (c[0] != "16" && c[0] != "32" && c[0] != "64")) continue;
    ++rows;
    EXPECT_TRUE(c[1] == "PCL GICP (gicp)" || c[1] == "Gauss-Newton GICP (gicp_gn)") << line;
    EXPECT_EQ(c[5], "3 / 3") << line;
    const double median_translation = std::stod(c[6].substr(0, c[6].find('/')));
    EXPECT_LT(median_translation, 0.02) << line;
  }
  EXPECT_EQ(rows, 6) << r.output;
}

TEST(BenchRegistration, BadOptionIsOneLineOfError) {
  const auto r = e2e::run(e2e::bin("lista-bench-registration") + " --offset -1 2>&1");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("--offset"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
}

TEST(BenchRegistration, DatasetScanPairsAreScoredAgainstTheTruth) {
  e2e::TempDir tmp("bench_registration");
  const auto data = tmp.path() / "tiny";
  const auto sim = e2e::simulate("--preset tiny --seed 1", data);
  ASSERT_EQ(sim.status, 0) << sim.output;
  const auto r = e2e::run(e2e::bin("lista-bench-registration") + " --dataset " + data.string() +
                          " --max-pairs 8 --threads 2 2>&1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("8 scan pairs of " + data.string()), std::string::npos) << r.output;
  // Median horizontal error of the pairs that pass the gates, per row.
  auto median_of = [](const std::string& cell) { return std::stod(cell.substr(0, cell.find('/'))); };
  std::map<std::string, double> horizontal;
  int rows = 0;
  for (const auto& c : e2e::markdown_rows(r.output)) {
    ASSERT_EQ(c.size(), 10u);
    ++rows;
    horizontal[c[0]] = median_of(c[7]);
    // The passed pairs' mean signed error along the step: millimetres, no
    // bias that would add up along a mission (well under the 1 mm errors'
    // scale times a few).
    EXPECT_LT(std::abs(std::stod(c[9])), 3.0) << c[0] << "\n" << r.output;
    if (c[0] == "odometry (poses.txt)") {
      EXPECT_EQ(c[1], "-");  // not a registration: untimed, every pair "passes"
      EXPECT_EQ(c[5], "8 / 8");
      continue;
    }
    EXPECT_TRUE(c[0] == "PCL GICP (gicp)" || c[0] == "Gauss-Newton GICP (gicp_gn)") << c[0];
    EXPECT_EQ(c[4], "8 / 8") << c[0];
    EXPECT_EQ(c[5], "8 / 8") << c[0];  // the tiny office, well seen by its XT32: every pair passes
  }
  // What the scans add: both registrations land nearer the truth than the
  // odometry they started from (about 1 mm against 6 mm).
  ASSERT_EQ(horizontal.count("odometry (poses.txt)"), 1u) << r.output;
  for (const char* method : {"PCL GICP (gicp)", "Gauss-Newton GICP (gicp_gn)"})
    EXPECT_LT(horizontal[method], 0.5 * horizontal["odometry (poses.txt)"]) << method << "\n" << r.output;
  EXPECT_EQ(rows, 3) << r.output;

  // Without poses_gt.txt there is nothing to score: one line says so.
  for (const auto& mission : std::filesystem::directory_iterator(data))
    if (mission.is_directory()) std::filesystem::remove(mission.path() / "poses_gt.txt");
  const auto bare = e2e::run(e2e::bin("lista-bench-registration") + " --dataset " + data.string() + " 2>&1");
  EXPECT_NE(bare.status, 0);
  EXPECT_NE(bare.output.find("no mission with poses_gt.txt"), std::string::npos) << bare.output;
  EXPECT_EQ(bare.output.find('\n'), bare.output.size() - 1) << "one line: " << bare.output;
}
