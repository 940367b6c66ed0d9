// lista-bench registration as a user runs it: both GICPs on the same pairs,
// one table row per sensor and method, every pair converged and near the
// truth (the numbers are measured by the program, not asserted as times).
#include "e2e_support.hpp"

#include <gtest/gtest.h>

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
