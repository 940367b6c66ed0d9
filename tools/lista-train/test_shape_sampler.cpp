// Batch composition: distinct shapes, equal shares per source when balanced,
// spill-over from a source that runs short, the uniform draw otherwise, and
// look-alike groups of shapes of nearly one size.
#include "shape_sampler.hpp"

#include <lista/error.hpp>

#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace {

// `shapes_per_source[s]` shapes of source s, two views each.
lista::objfeat::ViewSet views_of_sources(const std::vector<int>& shapes_per_source) {
  lista::objfeat::ViewSet set;
  int label = 0;
  for (size_t s = 0; s < shapes_per_source.size(); ++s) {
    set.sources.push_back("source-" + std::to_string(s));
    for (int k = 0; k < shapes_per_source[s]; ++k, ++label)
      for (int v = 0; v < 2; ++v) {
        lista::objfeat::View view;
        view.label = label;
        view.source = int(s);
        set.views.push_back(view);
      }
  }
  return set;
}

std::map<int, int> per_source(const lista::objfeat::ViewSet& set, const std::vector<int>& shapes) {
  std::map<int, int> count;
  for (int shape : shapes) ++count[set.views[size_t(shape) * 2].source];  // two views per shape, label order
  return count;
}

TEST(ShapeSampler, BalancedBatchesShareSlotsEvenlyAcrossSources) {
  const auto set = views_of_sources({60, 6, 20});
  lista::train::ShapeSampler sampler(set, 9, true);
  std::mt19937_64 rng(3);
  for (int step = 0; step < 50; ++step) {
    const auto shapes = sampler.draw(rng);
    ASSERT_EQ(shapes.size(), 9u);
    EXPECT_EQ(std::set<int>(shapes.begin(), shapes.end()).size(), 9u);
    const auto count = per_source(set, shapes);
    for (int s = 0; s < 3; ++s) EXPECT_EQ(count.at(s), 3) << "source " << s;
  }
}

TEST(ShapeSampler, ASourceShortOfShapesLeavesItsSlotsToTheOthers) {
  const auto set = views_of_sources({2, 40});
  lista::train::ShapeSampler sampler(set, 8, true);
  std::mt19937_64 rng(5);
  for (int step = 0; step < 20; ++step) {
    const auto shapes = sampler.draw(rng);
    ASSERT_EQ(std::set<int>(shapes.begin(), shapes.end()).size(), 8u);
    const auto count = per_source(set, shapes);
    EXPECT_EQ(count.at(0), 2);
    EXPECT_EQ(count.at(1), 6);
  }
}

TEST(ShapeSampler, UnbalancedDrawsFollowTheSourcesSizes) {
  const auto set = views_of_sources({90, 10});
  lista::train::ShapeSampler sampler(set, 10, false);
  std::mt19937_64 rng(7);
  int minority = 0;
  for (int step = 0; step < 200; ++step) {
    const auto shapes = sampler.draw(rng);
    ASSERT_EQ(std::set<int>(shapes.begin(), shapes.end()).size(), 10u);
    minority += per_source(set, shapes)[1];
  }
  EXPECT_NEAR(minority / 2000.0, 0.1, 0.03);  // 10% of shapes, 10% of slots
}

TEST(ShapeSampler, ShapesWithOneViewDoNotCountAndTooFewAreAnError) {
  auto set = views_of_sources({5});
  set.views.pop_back();  // shape 4 keeps one view
  lista::train::ShapeSampler sampler(set, 4, true);
  EXPECT_EQ(sampler.shapes(), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_THROW(lista::train::ShapeSampler(set, 5, true), lista::Error);
}

// Ten clusters of four shapes; a cluster's shapes are within 2% of one size
// and clusters are 50% apart. Two views per shape, one of them half hidden
// (a short extent), so the per-shape median must see through one bad view.
std::vector<Eigen::Vector3f> clustered_sizes(const lista::objfeat::ViewSet& set) {
  std::vector<Eigen::Vector3f> sizes;
  for (size_t i = 0; i < set.views.size(); ++i) {
    const int shape = set.views[i].label;
    const float size = std::pow(1.5f, float(shape / 4)) * (1.f + 0.005f * float(shape % 4));
    Eigen::Vector3f s(size, 0.5f * size, 0.8f * size);
    if (i % 2 == 1 && shape % 3 == 0) s.x() *= 0.6f;  // partial view of some shapes, never both views
    sizes.push_back(s);
  }
  return sizes;
}

TEST(ShapeSampler, LookalikeCandidatesAreTheShapesOfNearlyTheSameSize) {
  const auto set = views_of_sources({40});
  lista::train::ShapeSampler sampler(set, 8, 2, clustered_sizes(set));
  for (int shape = 0; shape < 40; ++shape) {
    const auto& near = sampler.lookalikes_of(shape);
    ASSERT_EQ(near.size(), size_t(lista::train::ShapeSampler::kLookalikeCandidates));
    std::set<int> first3(near.begin(), near.begin() + 3), mates;
    for (int k = 0; k < 4; ++k)
      if (shape / 4 * 4 + k != shape) mates.insert(shape / 4 * 4 + k);
    EXPECT_EQ(first3, mates) << "shape " << shape;
  }
}

TEST(ShapeSampler, LookalikeBatchesAreGroupsOfAnAnchorAndItsCandidates) {
  const auto set = views_of_sources({40});
  lista::train::ShapeSampler sampler(set, 12, 3, clustered_sizes(set));
  std::mt19937_64 rng(11);
  std::set<int> anchors;
  for (int step = 0; step < 100; ++step) {
    const auto shapes = sampler.draw(rng);
    ASSERT_EQ(shapes.size(), 12u);
    ASSERT_EQ(std::set<int>(shapes.begin(), shapes.end()).size(), 12u);
    for (size_t g = 0; g < shapes.size(); g += 3) {
      anchors.insert(shapes[g]);
      const auto& near = sampler.lookalikes_of(shapes[g]);
      for (size_t k = 1; k < 3; ++k)
        EXPECT_NE(std::find(near.begin(), near.end(), shapes[g + k]), near.end())
            << "shape " << shapes[g + k] << " is no look-alike of anchor " << shapes[g];
    }
  }
  EXPECT_GT(anchors.size(), 35u);  // anchors are drawn from all shapes
}

TEST(ShapeSampler, LookalikeShareGroupsTheFirstSlotsAndLeavesTheRestUniform) {
  const auto set = views_of_sources({40});
  const auto sizes = clustered_sizes(set);
  lista::train::ShapeSampler half(set, 12, 3, sizes, 0.5), none(set, 12, 3, sizes, 0.0), uniform(set, 12, false);
  std::mt19937_64 rng(13), a(17), b(17);
  for (int step = 0; step < 50; ++step) {
    const auto shapes = half.draw(rng);
    ASSERT_EQ(std::set<int>(shapes.begin(), shapes.end()).size(), 12u);
    for (size_t g = 0; g < 6; g += 3) {
      const auto& near = half.lookalikes_of(shapes[g]);
      for (size_t k = 1; k < 3; ++k) EXPECT_NE(std::find(near.begin(), near.end(), shapes[g + k]), near.end());
    }
    // No grouped slots: exactly the uniform draw, which draw_uniform also gives.
    const auto plain = uniform.draw(b);
    EXPECT_EQ(none.draw(a), plain);
  }
  // The pools are shuffled in place, so compare samplers that drew alike.
  lista::train::ShapeSampler fresh_half(set, 12, 3, sizes, 0.5), fresh_uniform(set, 12, false);
  std::mt19937_64 c(19), d(19);
  EXPECT_EQ(fresh_half.draw_uniform(c), fresh_uniform.draw(d));
  lista::train::ShapeSampler balanced(set, 12, true);
  EXPECT_THROW(balanced.draw_uniform(c), lista::Error);
}

TEST(ShapeSampler, LookalikeGroupsRejectBadArguments) {
  const auto set = views_of_sources({10});
  auto sizes = clustered_sizes(set);
  EXPECT_THROW(lista::train::ShapeSampler(set, 4, 0, sizes), lista::Error);
  EXPECT_THROW(lista::train::ShapeSampler(set, 4, 2, sizes, 1.5), lista::Error);
  sizes.pop_back();
  EXPECT_THROW(lista::train::ShapeSampler(set, 4, 2, sizes), lista::Error);
}

}  // namespace
