#include <lista_grouping/group_result.hpp>
#include "kmeans.hpp"
#include <lista_testing/plugin_stage.hpp>

#include <lista/basic_context.hpp>

#include <gtest/gtest.h>
#include <random>
#include <set>

using namespace lista;
using namespace lista::group;

namespace {

// k well separated Gaussian blobs of `per` points in `dim` dimensions.
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
      d.object_ids.push_back(100 + c * per + i);
    }
  }
  return d;
}

Groups run_stage(const DescriptorSet& d, std::map<std::string, ParamValue> p = {}, uint64_t seed = 7) {
  auto stage = plugin_test::make_stage("group.kmeans", p);
  BasicContext ctx("group", 1, seed);
  Inputs in;
  in.set("descriptors", Data::make(d));
  return stage->run(in, ctx).at("groups").as<Groups>();
}

}  // namespace

TEST(ElbowRule, FindsPlantedK) {
  for (int k : {2, 3, 4, 5}) {
    const DescriptorSet d = blobs(k, 6, 16, 0.3, 11 + k);
    const Groups g = run_stage(d);
    EXPECT_EQ(g.count, k);
    // Objects of one blob share one group, and blobs get different groups.
    std::set<int> seen;
    for (int c = 0; c < k; ++c) {
      for (int i = 1; i < 6; ++i) EXPECT_EQ(g.group[c * 6 + i], g.group[c * 6]);
      seen.insert(g.group[c * 6]);
    }
    EXPECT_EQ(static_cast<int>(seen.size()), k);
  }
}

TEST(ElbowRule, CurveShapes) {
  EXPECT_EQ(elbow_k({10.0}), 1);
  EXPECT_EQ(elbow_k({10.0, 1.0}), 1);
  EXPECT_EQ(elbow_k({100.0, 10.0, 8.0, 7.0, 6.0}), 2);
  EXPECT_EQ(elbow_k({100.0, 90.0, 5.0, 4.0, 3.0}), 3);
  EXPECT_EQ(elbow_k({5.0, 5.0, 5.0}), 1);  // flat: one class
}

TEST(KMeans, TinyInputs) {
  for (int n : {0, 1, 2, 3}) {
    DescriptorSet d;
    d.values.resize(n, 4);
    for (int i = 0; i < n; ++i) {
      d.values.row(i).setConstant(static_cast<float>(i * 5));
      d.object_ids.push_back(i);
    }
    const Groups g = run_stage(d);
    EXPECT_EQ(g.group.size(), static_cast<size_t>(n));
    EXPECT_EQ(g.confidence.size(), static_cast<size_t>(n));
    if (n > 0) {
      EXPECT_GE(g.count, 1);
      EXPECT_LE(g.count, n);
    } else {
      EXPECT_EQ(g.count, 0);
    }
    if (n <= 2) {
      EXPECT_EQ(g.count, n == 0 ? 0 : 1);
    }
  }
}

TEST(KMeans, FixedKAndDeterminism) {
  const DescriptorSet d = blobs(3, 8, 8, 1.5, 3);
  const Groups a = run_stage(d, {{"k", int64_t{4}}}, 42);
  const Groups b = run_stage(d, {{"k", int64_t{4}}}, 42);
  EXPECT_EQ(a.count, 4);
  EXPECT_EQ(a.group, b.group);
  EXPECT_EQ(a.confidence, b.confidence);
}

TEST(KMeans, RejectsBadDescriptors) {
  DescriptorSet d = blobs(2, 3, 4, 0.1, 1);
  d.values(0, 0) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(run_stage(d), Error);
  DescriptorSet e = blobs(2, 3, 4, 0.1, 1);
  e.object_ids.pop_back();
  EXPECT_THROW(run_stage(e), Error);
}

TEST(Confidence, PaperMapping) {
  // Cluster 0 tight (spread 0.1), cluster 1 loose (spread 1): 0 is the most compact.
  Eigen::MatrixXd x(6, 1);
  x << 0.0, 0.1, -0.1, 10.0, 11.0, 9.0;
  const Groups g = grouping::make_groups("t", {1, 2, 3, 4, 5, 6}, x, {0, 0, 0, 1, 1, 1});
  ASSERT_EQ(g.count, 2);
  EXPECT_DOUBLE_EQ(g.group_confidence[0], 1.0);
  EXPECT_DOUBLE_EQ(g.group_confidence[1], 0.0);
  // Objects on their centroid are fully confident; the farthest gets 0.
  EXPECT_DOUBLE_EQ(g.confidence[0], 1.0);
  EXPECT_DOUBLE_EQ(g.confidence[3], 1.0);
  EXPECT_NEAR(g.confidence[4], 0.0, 1e-12);
  EXPECT_NEAR(g.confidence[1], 0.9, 1e-12);
  EXPECT_EQ(g.group_of(5), 1);
}
