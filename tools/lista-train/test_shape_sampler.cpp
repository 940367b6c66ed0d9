// Batch composition: distinct shapes, equal shares per source when balanced,
// spill-over from a source that runs short, and the uniform draw otherwise.
#include "shape_sampler.hpp"

#include <lista/error.hpp>

#include <gtest/gtest.h>
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

}  // namespace
