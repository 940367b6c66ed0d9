#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

using namespace test_support;

TEST(FilterBox, KeepsPointsInsideTheBoxWithProvenance) {
  lista::PointSet s;
  for (int i = 0; i < 10; ++i) add_point(s, {float(i), 0, 0});
  auto out = run_stage("filter.box", "changes", lista::Data::make(missions({s, s})),
                       {{"min", std::vector<double>{2, -1, -1}}, {"max", std::vector<double>{5, 1, 1}}});
  const auto& mp = out.at("changes").as<lista::MissionPoints>();
  ASSERT_EQ(mp.sets.size(), 2u);
  ASSERT_EQ(mp.sets[1].size(), 4u);
  EXPECT_EQ(mp.sets[1].index, (std::vector<uint32_t>{2, 3, 4, 5}));
}

TEST(FilterBox, CutsTheCeilingMeasuredFromTheFloor) {
  lista::PointSet s;
  for (int i = 0; i < 200; ++i) add_point(s, {float(i % 10), 0, 10.0f + 0.02f * float(i)});  // 10..14 m
  add_point(s, {0, 0, 5.0f});  // one stray point under the floor must not move it
  auto out = run_stage("filter.box", "changes", lista::Data::make(missions({s})),
                       {{"max_height_above_floor", 2.0}});
  const auto& kept = out.at("changes").as<lista::MissionPoints>().sets[0];
  // floor = 1% quantile ~ 10.04; keep z <= ~12.04 (and the stray point).
  EXPECT_GT(kept.size(), 95u);
  EXPECT_LT(kept.size(), 105u);
  for (const auto& p : kept.xyz) EXPECT_LE(p.z(), 12.1f);
}

TEST(FilterBox, RejectsInvertedCorners) {
  lista::PointSet s;
  EXPECT_THROW(run_stage("filter.box", "changes", lista::Data::make(missions({s})),
                         {{"min", std::vector<double>{1, 0, 0}}, {"max", std::vector<double>{0, 1, 1}}}),
               lista::Error);
}
