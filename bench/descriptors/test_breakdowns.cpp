// Top-1 breakdowns of lista-bench-descriptors: every view lands in the bin
// its size, sensor, distance or coverage says, views the folder says
// nothing about land in none, and each bin counts its own hits.
#include "breakdowns.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace {

// A view of a 1 m tall shape spanning z in [lo, hi], `points` points.
lista::objfeat::View view(float lo, float hi, size_t points = 2, const std::string& sensor = "",
                          float distance = std::nanf("")) {
  lista::objfeat::View v;
  v.points.xyz.assign(points, Eigen::Vector3f(0.f, 0.f, lo));
  v.points.xyz.back().z() = hi;
  v.extent = {0.5f, 0.4f, 1.0f};
  v.sensor = sensor;
  v.distance = distance;
  return v;
}

TEST(BenchBreakdowns, CoverageComparesTheViewWithItsShapesHeight) {
  lista::objfeat::ViewSet set;
  set.views = {view(0.0f, 1.0f), view(0.2f, 1.0f), view(0.0f, 0.8f), view(0.3f, 0.6f),
               view(0.14f, 0.86f)};  // within 10 % + 5 cm at both ends: whole
  lista::objfeat::View unknown = view(0.5f, 0.6f);
  unknown.extent[2] = std::nanf("");
  set.views.push_back(unknown);
  const auto b = lista::bench::by_coverage(set);
  EXPECT_EQ(b.bin_of, (std::vector<int>{0, 1, 2, 3, 0, -1}));
  EXPECT_EQ(b.bins[size_t(b.bin_of[1])], "bottom missed");
  EXPECT_FALSE(b.empty());
}

TEST(BenchBreakdowns, SizeSensorAndDistanceBins) {
  lista::objfeat::ViewSet set;
  set.views = {view(0, 1, 64, "vlp16", 2.9f), view(0, 1, 65, "os0-128", 3.0f), view(0, 1, 1500, "vlp16", 12.5f),
               view(0, 1, 300)};
  const auto size = lista::bench::by_view_size(set);
  EXPECT_EQ(size.bin_of, (std::vector<int>{0, 1, 3, 2}));
  const auto sensor = lista::bench::by_sensor(set);
  EXPECT_EQ(sensor.bins, (std::vector<std::string>{"os0-128", "vlp16"}));
  EXPECT_EQ(sensor.bin_of, (std::vector<int>{1, 0, 1, -1}));
  const auto distance = lista::bench::by_distance(set);
  EXPECT_EQ(distance.bins, (std::vector<std::string>{"0-3", "3-5", "5-8", "8-12", ">= 12"}));
  EXPECT_EQ(distance.bin_of, (std::vector<int>{0, 1, 4, -1}));

  const auto scores = lista::bench::score_bins(sensor, {1, 0, 0, 1});
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_EQ(scores[0].views, 1u);
  EXPECT_EQ(scores[0].hits, 0u);
  EXPECT_EQ(scores[1].views, 2u);  // the sensor-less view counts nowhere
  EXPECT_DOUBLE_EQ(scores[1].top1(), 0.5);
  // A view alone with its shape (-1: no query) counts in no bin, as top-1
  // leaves it out.
  const auto lone = lista::bench::score_bins(sensor, {1, -1, 0, 1});
  EXPECT_EQ(lone[0].views, 0u);
  EXPECT_EQ(lone[1].views, 2u);
}

TEST(BenchBreakdowns, AFolderThatSaysNothingGivesAnEmptyBreakdown) {
  lista::objfeat::ViewSet set;
  set.views = {view(0, 1), view(0, 1)};
  EXPECT_TRUE(lista::bench::by_sensor(set).empty());
  EXPECT_TRUE(lista::bench::by_sensor(set).bins.empty());
  EXPECT_TRUE(lista::bench::by_distance(set).empty());
  EXPECT_FALSE(lista::bench::by_view_size(set).empty());
}

}  // namespace
