#include "hungarian.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

using namespace lista::match;

namespace {
double total(const Eigen::MatrixXd& c, const std::vector<int>& a) {
  double s = 0;
  for (size_t i = 0; i < a.size(); ++i) s += c(i, a[i]);
  return s;
}
}  // namespace

TEST(Hungarian, HandCaseWhereGreedyFails) {
  // Greedy takes (0,0)=1 then must take (1,1)=10: total 11. Optimal: 2 + 3 = 5.
  Eigen::MatrixXd c(2, 2);
  c << 1, 2, 3, 10;
  const auto a = hungarian(c);
  EXPECT_EQ(a, (std::vector<int>{1, 0}));
  EXPECT_DOUBLE_EQ(total(c, a), 5.0);
}

TEST(Hungarian, ClassicThreeByThree) {
  Eigen::MatrixXd c(3, 3);
  c << 4, 1, 3, 2, 0, 5, 3, 2, 2;  // optimum 5: (0,1) (1,0) (2,2)
  const auto a = hungarian(c);
  EXPECT_DOUBLE_EQ(total(c, a), 5.0);
}

TEST(Hungarian, MatchesBruteForceOnRandomRectangles) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 10);
  for (int trial = 0; trial < 50; ++trial) {
    const int n = 1 + trial % 5, m = n + trial % 3;
    Eigen::MatrixXd c(n, m);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j) c(i, j) = u(rng);
    std::vector<int> cols(m);
    std::iota(cols.begin(), cols.end(), 0);
    double best = 1e18;
    do {
      best = std::min(best, total(c, std::vector<int>(cols.begin(), cols.begin() + n)));
    } while (std::next_permutation(cols.begin(), cols.end()));
    EXPECT_NEAR(total(c, hungarian(c)), best, 1e-9);
  }
}

TEST(AssignWithGate, PairsOnlyBelowTheLeaveCost) {
  Eigen::MatrixXd c(2, 3);
  c << 0.2, 0.9, 5.0, 5.0, 5.0, 1.5;
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> ok;
  ok.setConstant(2, 3, true);
  EXPECT_EQ(assign_with_gate(c, ok, 1.0), (std::vector<int>{0, -1}));
  EXPECT_EQ(assign_with_gate(c, ok, 2.0), (std::vector<int>{0, 2}));
  ok(0, 0) = false;  // forbidden pairs are never used
  EXPECT_EQ(assign_with_gate(c, ok, 1.0), (std::vector<int>{1, -1}));
  EXPECT_TRUE(assign_with_gate(Eigen::MatrixXd(0, 2), ok.topRows(0), 1.0).empty());
}
