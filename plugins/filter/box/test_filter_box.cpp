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

// With the aligned missions connected, the floor is the scene's: changes
// that all stand 1 m off the floor (no change on it) are measured from the
// floor the scans saw, not from the lowest change.
TEST(FilterBox, TakesTheFloorFromTheMissionsWhenGiven) {
  lista::PointSet changes;
  for (int i = 0; i <= 300; ++i) add_point(changes, {float(i % 10), 0, 1.0f + 0.01f * float(i)});  // 1..4 m
  auto scan = std::make_shared<lista::PointSet>();
  for (int i = 0; i < 1000; ++i) add_point(*scan, {float(i % 30), float(i / 30), 0.0f});  // the floor, z = 0
  for (int i = 0; i < 100; ++i) add_point(*scan, {float(i % 10), 0, 1.0f + 0.03f * float(i)});
  lista::MissionSet set;
  set.missions.resize(1);
  set.missions[0].name = "m0";
  set.missions[0].scans.resize(1);
  set.missions[0].scans[0].points = scan;
  set.missions[0].scans[0].pose.translation() = Eigen::Vector3d(0, 0, 0.5);  // sensor pose applies
  set.missions[0].to_common.translation() = Eigen::Vector3d(0, 0, -0.5);

  auto stage = lista::plugin_test::make_stage("filter.box", {{"max_height_above_floor", 2.5}});
  lista::Inputs in;
  in.set("changes", lista::Data::make(missions({changes})));
  lista::BasicContext context("test", 1, 7);
  const auto without = stage->run(in, context).at("changes").as<lista::MissionPoints>().sets[0];
  for (const auto& p : without.xyz) EXPECT_LE(p.z(), 3.55f) << "floor read from the changes: about 1 m";
  in.set("missions", lista::Data::make(set));
  const auto with = stage->run(in, context).at("changes").as<lista::MissionPoints>().sets[0];
  EXPECT_LT(with.size(), without.size());
  for (const auto& p : with.xyz) EXPECT_LE(p.z(), 2.55f) << "floor read from the scans: about 0 m";
  EXPECT_GT(with.size(), 140u);
}
