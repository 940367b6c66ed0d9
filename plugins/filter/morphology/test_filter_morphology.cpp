#include "morphology.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

using namespace test_support;

TEST(FilterMorphology, RemovesNoiseAndSliverKeepsSmallObject) {
  std::mt19937 rng(1);
  lista::PointSet s;
  // A small object: 0.3 m box surface (3x3x3 voxels of 0.1 m), dense.
  add_box_surface(s, {0.01f, 0.01f, 0.01f}, {0.29f, 0.29f, 0.29f}, 0.02f);
  const size_t object = s.size();
  // Isolated noise points far from each other.
  std::uniform_real_distribution<float> u(3.f, 9.f);
  for (int i = 0; i < 30; ++i) add_point(s, {u(rng), u(rng), u(rng)});
  // A sliver: a 2 m long strip, 2 voxels wide, 1 voxel thick (a wall edge).
  for (float x = 0; x < 2.f; x += 0.02f)
    for (float y = 0.01f; y < 0.2f; y += 0.03f) add_point(s, {x, y + 2.f, 1.05f});
  auto keep = lista::filter::morphology_keep(s, lista::filter::MorphologyConfig{});
  // Every point of the object survives (its corners come back by dilation), nothing else.
  ASSERT_EQ(keep.size(), object);
  for (size_t k = 0; k < keep.size(); ++k) EXPECT_EQ(keep[k], k);
}

TEST(FilterMorphology, ReconstructionKeepsThinPartsOfAnObject) {
  // A table: a 0.8 m square top and four 1-voxel-thin legs 0.7 m long;
  // apart from it, a lone 2-voxel-wide sliver.
  lista::PointSet s;
  for (float x = 0.005f; x < 0.8f; x += 0.02f)
    for (float y = 0.005f; y < 0.8f; y += 0.02f) add_point(s, {x, y, 0.75f});
  for (float lx : {0.05f, 0.75f})
    for (float ly : {0.05f, 0.75f})
      for (float z = 0.005f; z < 0.74f; z += 0.02f) add_point(s, {lx, ly, z});
  const size_t table = s.size();
  for (float x = 0; x < 2.f; x += 0.02f)
    for (float y = 0.01f; y < 0.2f; y += 0.03f) add_point(s, {x + 3.f, y, 1.05f});
  lista::filter::MorphologyConfig c;
  auto keep = lista::filter::morphology_keep(s, c);
  ASSERT_EQ(keep.size(), table);  // the whole table, legs included; no sliver
  EXPECT_EQ(keep.back(), table - 1);
  // A plain opening (one dilation) loses most of each leg.
  c.reconstruct = false;
  const size_t opened = lista::filter::morphology_keep(s, c).size();
  EXPECT_LT(opened, table - 100);
}

TEST(FilterMorphology, ThreeWideStripSurvivesWhole) {
  lista::PointSet s;
  for (float x = 0.005f; x < 2.f; x += 0.02f)
    for (float y = 0.005f; y < 0.3f; y += 0.02f) add_point(s, {x, y, 0.05f});
  auto keep = lista::filter::morphology_keep(s, lista::filter::MorphologyConfig{});
  EXPECT_EQ(keep.size(), s.size());
}

TEST(FilterMorphology, StageOutputsOriginalPointsWithProvenance) {
  lista::PointSet a;
  add_box_surface(a, {0.01f, 0.01f, 0.01f}, {0.49f, 0.49f, 0.49f}, 0.03f, 5);
  add_point(a, {7, 7, 7});
  auto out = run_stage("filter.morphology", "changes", lista::Data::make(missions({a, a})));
  const auto& mp = out.at("changes").as<lista::MissionPoints>();
  ASSERT_EQ(mp.sets.size(), 2u);
  EXPECT_EQ(mp.sets[0].size(), a.size() - 1);
  EXPECT_EQ(mp.sets[1].xyz[3], a.xyz[3]);  // positions untouched
  EXPECT_EQ(mp.sets[1].scan[0], 5u);
}
