#include <lista_testing/plugin_stage.hpp>
#include "agglomerative.hpp"

#include <lista/basic_context.hpp>

#include <gtest/gtest.h>
#include <algorithm>
#include <random>
#include <set>

using namespace lista;
using namespace lista::group;

namespace {

DescriptorSet blobs(int k, int per, int dim, double spread, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, spread);
  std::uniform_real_distribution<double> centre(-10.0, 10.0);
  DescriptorSet d;
  d.values.resize(k * per, dim);
  for (int c = 0; c < k; ++c) {
    Eigen::VectorXd mu(dim);
    for (int j = 0; j < dim; ++j) mu[j] = centre(rng);
    for (int i = 0; i < per; ++i) {
      for (int j = 0; j < dim; ++j) d.values(c * per + i, j) = static_cast<float>(mu[j] + noise(rng));
      d.object_ids.push_back(c * per + i);
    }
  }
  return d;
}

// Clusters centred on one axis at `positions`, each `per` points of Gaussian
// spread: well separated, but some much farther apart than others.
DescriptorSet clusters_on_a_line(const std::vector<double>& positions, int per, int dim, double spread, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, spread);
  DescriptorSet d;
  d.values.resize(static_cast<int>(positions.size()) * per, dim);
  int row = 0;
  for (double x : positions)
    for (int i = 0; i < per; ++i, ++row) {
      for (int j = 0; j < dim; ++j) d.values(row, j) = static_cast<float>((j == 0 ? x : 0.0) + noise(rng));
      d.object_ids.push_back(row);
    }
  return d;
}

Groups run_stage(const DescriptorSet& d, std::map<std::string, ParamValue> p = {}, BasicContext* log = nullptr) {
  auto stage = plugin_test::make_stage("group.agglomerative", p);
  BasicContext own;
  BasicContext& ctx = log ? *log : own;
  Inputs in;
  in.set("descriptors", Data::make(d));
  return stage->run(in, ctx).at("groups").as<Groups>();
}

void expect_blobs(const Groups& g, int k, int per) {
  ASSERT_EQ(g.count, k);
  std::set<int> seen;
  for (int c = 0; c < k; ++c) {
    for (int i = 1; i < per; ++i) EXPECT_EQ(g.group[c * per + i], g.group[c * per]);
    seen.insert(g.group[c * per]);
  }
  EXPECT_EQ(static_cast<int>(seen.size()), k);
}

}  // namespace

TEST(Agglomerative, EveryLinkageFindsPlantedGroupsAtTheGap) {
  for (const char* linkage : {"single", "average", "complete", "ward"}) {
    SCOPED_TRACE(linkage);
    expect_blobs(run_stage(blobs(3, 5, 16, 0.2, 5), {{"linkage", std::string(linkage)}}), 3, 5);
  }
}

// Ten or more objects per class, as a real scene gives: the cut is where
// the merge heights jump, whatever the linkage.
TEST(Agglomerative, GapCutFindsWellSeparatedClassesOfTenOrMore) {
  for (const char* linkage : {"single", "average", "complete", "ward"}) {
    SCOPED_TRACE(linkage);
    for (int k : {2, 3, 5, 7}) {
      SCOPED_TRACE(k);
      expect_blobs(run_stage(blobs(k, 12, 16, 1.0, 20 + k), {{"linkage", std::string(linkage)}}), k, 12);
    }
  }
}

// Classes 8, 16 and 32 units apart: the jump from the spread inside a class
// (about 2) to the nearest two classes' distance is the largest relative
// one, though the top merges are farther apart in absolute terms.
TEST(Agglomerative, GapCutIsRelativeSoUnevenlySpacedClassesAllCount) {
  expect_blobs(run_stage(clusters_on_a_line({0.0, 8.0, 24.0, 56.0}, 12, 8, 0.3, 1)), 4, 12);
}

TEST(Agglomerative, OneBlobIsOneGroupWithAWarning) {
  for (int dim : {8, 16}) {
    SCOPED_TRACE(dim);
    BasicContext ctx;
    EXPECT_EQ(run_stage(blobs(1, 40, dim, 1.0, 3), {}, &ctx).count, 1);
    const bool warned = std::any_of(ctx.messages.begin(), ctx.messages.end(),
                                    [](const std::string& m) { return m.find("no jump") != std::string::npos; });
    EXPECT_TRUE(warned) << "one group by the gap cut says why";
  }
}

// A moved object is described in both missions: near-identical pairs. Their
// tiny merges are not classes; one blob of pairs is still one group.
TEST(Agglomerative, NearDuplicatePairsAreNotClasses) {
  const DescriptorSet objects = blobs(1, 20, 16, 1.0, 4);
  DescriptorSet d;
  d.values.resize(40, 16);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 16; ++j) d.values(i, j) = objects.values(i / 2, j) + static_cast<float>(i % 2 ? noise(rng) : 0.0);
    d.object_ids.push_back(i);
  }
  EXPECT_EQ(run_stage(d).count, 1);
}

TEST(Agglomerative, LargestJumpHandComputed) {
  // Only the heights count. Eight objects: at most 4 groups are considered;
  // the jumps above 4, 3 and 2 groups are x2.5, x1.1 and x1.21.
  std::vector<Merge> m;
  for (double h : {1.0, 1.0, 1.1, 1.2, 3.0, 3.3, 4.0}) m.push_back({0, 1, h});
  const GapCut g = cut_at_largest_gap(8, m, 0.5, 10);
  EXPECT_EQ(g.k, 4);
  EXPECT_EQ(g.best_k, 4);
  EXPECT_NEAR(g.jump, 1.5, 1e-12);
  EXPECT_EQ(cut_at_largest_gap(8, m, 1.6, 10).k, 1);  // x2.5 is not 160 % more
  const GapCut top = cut_at_largest_gap(8, m, 0.5, 3);  // k_max 3: the x2.5 jump is not looked at
  EXPECT_EQ(top.k, 1);
  EXPECT_EQ(top.best_k, 2);
  EXPECT_NEAR(top.jump, 4.0 / 3.3 - 1.0, 1e-12);
  // Identical rows merge at height 0: any jump above them is infinitely large.
  const std::vector<Merge> twins = {{0, 1, 0.0}, {2, 3, 0.0}, {0, 2, 2.0}};
  EXPECT_EQ(cut_at_largest_gap(4, twins, 0.5, 10).k, 2);
  // Fewer than four objects cannot make two groups of two.
  EXPECT_EQ(cut_at_largest_gap(3, {{0, 1, 0.1}, {0, 2, 5.0}}, 0.5, 10).k, 1);
}

TEST(Agglomerative, CutByKAndDistance) {
  const DescriptorSet d = blobs(4, 4, 8, 0.1, 9);
  expect_blobs(run_stage(d, {{"cut", std::string("k")}, {"k", int64_t{4}}}), 4, 4);
  // Within-blob distances are ~0.4, between blobs several units.
  expect_blobs(run_stage(d, {{"cut", std::string("distance")}, {"distance", 2.0}}), 4, 4);
  EXPECT_EQ(run_stage(d, {{"cut", std::string("distance")}, {"distance", 1e6}}).count, 1);
}

TEST(Agglomerative, HandComputedSingleLinkage) {
  Eigen::MatrixXd x(4, 1);
  x << 0.0, 1.0, 5.0, 5.5;
  const auto m = dendrogram(x, Linkage::single);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_DOUBLE_EQ(m[0].height, 0.5);
  EXPECT_DOUBLE_EQ(m[1].height, 1.0);
  EXPECT_DOUBLE_EQ(m[2].height, 4.0);
  EXPECT_EQ(cut_to_k(4, m, 2), (std::vector<int>{0, 0, 1, 1}));
}

TEST(Agglomerative, TinyInputs) {
  for (int n : {0, 1, 2, 3}) {
    DescriptorSet d;
    d.values.resize(n, 2);
    for (int i = 0; i < n; ++i) {
      d.values.row(i).setConstant(static_cast<float>(i));
      d.object_ids.push_back(i);
    }
    const Groups g = run_stage(d);
    EXPECT_EQ(g.group.size(), static_cast<size_t>(n));
    EXPECT_EQ(g.count, n == 0 ? 0 : 1);  // fewer than 4 objects: no two groups of two
  }
}
