#include "mls_smoothing.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

using namespace test_support;

TEST(FilterMls, FlattensNoisyPlaneKeepsOnePointPerInput) {
  std::mt19937 rng(1);
  std::normal_distribution<float> noise(0.f, 0.01f);
  lista::PointSet s;
  for (float x = 0; x < 1.f; x += 0.02f)
    for (float y = 0; y < 1.f; y += 0.02f) add_point(s, {x, y, 0.5f + noise(rng)});
  add_point(s, {5, 5, 5});  // alone: cannot be fitted
  auto rms = [](const lista::PointSet& p) {
    double e = 0;
    for (size_t i = 0; i + 1 < p.size(); ++i) e += std::pow(p.xyz[i].z() - 0.5, 2);
    return std::sqrt(e / double(p.size() - 1));
  };
  size_t fitted = 0;
  auto out = lista::filter::mls_smooth(s, lista::filter::MlsConfig{}, 2, &fitted);
  ASSERT_EQ(out.size(), s.size());
  EXPECT_EQ(out.index, s.index);
  EXPECT_EQ(fitted, s.size() - 1);
  EXPECT_LT(rms(out), 0.5 * rms(s));
  EXPECT_EQ(out.xyz.back(), s.xyz.back());  // unfitted point unchanged
  // Points move along the surface normal only, by about the noise.
  for (size_t i = 0; i + 1 < s.size(); ++i) EXPECT_LT((out.xyz[i] - s.xyz[i]).norm(), 0.06f);

  lista::filter::MlsConfig drop;
  drop.drop_unfitted = true;
  EXPECT_EQ(lista::filter::mls_smooth(s, drop, 1).size(), s.size() - 1);
}

TEST(FilterMls, StageKeepsMissionsAndProvenance) {
  lista::PointSet a;
  add_box_surface(a, {0, 0, 0}, {0.4f, 0.4f, 0.4f}, 0.02f, 2);
  auto out = run_stage("filter.mls", "changes", lista::Data::make(missions({a, a})));
  const auto& mp = out.at("changes").as<lista::MissionPoints>();
  ASSERT_EQ(mp.sets.size(), 2u);
  EXPECT_EQ(mp.sets[1].size(), a.size());
  EXPECT_EQ(mp.sets[1].scan, a.scan);
}
