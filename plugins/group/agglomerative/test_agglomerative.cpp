#include "../kmeans/stage_harness.hpp"
#include "agglomerative.hpp"

#include <lista/basic_context.hpp>

#include <gtest/gtest.h>
#include <random>
#include <set>

using namespace lista;
using namespace lista::grouping;

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

Groups run_stage(const DescriptorSet& d, std::map<std::string, ParamValue> p = {}) {
  auto stage = stage_test::make_stage("group.agglomerative", p);
  BasicContext ctx;
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
    EXPECT_EQ(g.count, n == 0 ? 0 : 1);  // evenly spaced: no gap, one class
  }
}
