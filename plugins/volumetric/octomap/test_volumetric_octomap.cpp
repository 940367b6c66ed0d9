// volumetric.octomap on the synthetic two-room scene.
#include "volumetric_octomap.hpp"

#include <lista_testing/expect_volumetric_params.hpp>
#include <lista_testing/memory_cap.hpp>

#include <lista/basic_context.hpp>
#include <lista_raycast/scene_checks.hpp>
#include <lista_raycast/synthetic_scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>

using namespace lista;

namespace {

const MissionSet& scene() {
  // Several scans per spot, as a moving sensor gives: occupancy needs repeated evidence.
  raycast::SyntheticSceneConfig c;
  c.rings = 16;
  c.columns = 360;
  c.scans_per_position = 4;
  static const MissionSet s = raycast::make_synthetic_scene(c);
  return s;
}

MissionPoints run_stage(const Params& p, const MissionSet& missions, int threads, BasicContext* ctx_out = nullptr) {
  BasicContext ctx("diff", threads);
  Inputs in;
  in.set("missions", Data::make(missions));
  Outputs o = volumetric::make_volumetric_octomap(p)->run(in, ctx);
  if (ctx_out) ctx_out->info = ctx.info;
  return o.at("changes").as<MissionPoints>();
}

Params defaults() { return Params::defaults(volumetric::volumetric_octomap_info().params); }

// Under a 1 GiB address-space cap above what the process maps now, a
// 5 mm map of the scene; exits 3 with the stage's error on stderr, 0 if
// there was none.
[[noreturn]] void build_too_big_a_map() {
  test_support::cap_address_space(rlim_t(1) << 30);
  Params fine = defaults();
  fine.set("resolution", 0.005);
  test_support::exit_3_on_error([&] { run_stage(fine, scene(), 2); });
}

}  // namespace

// A map that would outgrow the memory stops with an error that says what
// to change, not with std::bad_alloc inside an OpenMP region (std::terminate).
TEST(VolumetricOctomapDeathTest, AMapOutgrowingTheMemoryIsAClearError) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(build_too_big_a_map(), ::testing::ExitedWithCode(3),
              "occupancy maps? outgrows? the .*memory.* at resolution 0.005 m");
}

TEST(VolumetricOctomap, FindsRemovedAndAddedBoxesOnly) {
  BasicContext ctx;
  const MissionPoints ch = run_stage(defaults(), scene(), 2, &ctx);
  ASSERT_EQ(ch.sets.size(), 2u);
  const auto all_a = raycast::label_counts(scene().missions[0]);
  const auto all_b = raycast::label_counts(scene().missions[1]);
  auto got_a = raycast::label_counts(ch.sets[0]);
  auto got_b = raycast::label_counts(ch.sets[1]);
  for (const auto& [l, n] : got_a) std::cout << "A label " << l << ": " << n << " of " << all_a.at(l) << "\n";
  for (const auto& [l, n] : got_b) std::cout << "B label " << l << ": " << n << " of " << all_b.at(l) << "\n";
  // A box point is found only where a beam of the other mission crossed its
  // voxel; this sparse test scanner (16 rings, 6 deg apart) crosses about 60%.
  EXPECT_GT(got_a[1], 0.5 * all_a.at(1));
  EXPECT_GT(got_b[3], 0.45 * all_b.at(3));
  EXPECT_EQ(got_a[2], 0u);  // never observed in B: unknown, not change
  EXPECT_LT(got_a[0], 0.002 * all_a.at(0));
  EXPECT_LT(got_b[0], 0.002 * all_b.at(0));
  EXPECT_EQ(got_a[4] + got_b[4], 0u);
  const auto& metrics = ctx.info.metrics.at("diff");
  EXPECT_GT(metrics.at("A.occupied_voxels"), 0.0);
  EXPECT_EQ(metrics.at("B.changed_points"), static_cast<double>(ch.sets[1].size()));
}

TEST(VolumetricOctomap, RejectsBadParameters) {
  Params p = defaults();
  p.set("prob_miss", 0.6);
  EXPECT_THROW(volumetric::make_volumetric_octomap(p), Error);
  p = defaults();
  p.set("clamping_max", 0.05);
  EXPECT_THROW(volumetric::make_volumetric_octomap(p), Error);
}

TEST(VolumetricOctomap, MaxRangeIsFiniteAndNotNegative) {
  volumetric::testing::expect_max_range_finite_and_not_negative(volumetric::volumetric_octomap_info());
}

TEST(VolumetricOctomap, GrazeHeightReachesTheRayCasting) {
  volumetric::testing::expect_graze_height_shortens_floor_beams(defaults(), [](const Params& p) {
    BasicContext ctx;
    run_stage(p, scene(), 2, &ctx);
    return ctx.info.metrics.at("diff").at("A.free_voxels");
  });
}

// Three or more missions are built in mission order, two trees at a time:
// the same change as two missions give where the neighbours are the same
// (a third mission that repeats the first).
TEST(VolumetricOctomap, ThreeMissionsTwoTreesAtATimeGiveTheSameChange) {
  const MissionPoints two = run_stage(defaults(), scene(), 2);
  MissionSet three = scene();
  three.missions.push_back(three.missions[0]);
  three.missions.back().name = "C";
  const MissionPoints got = run_stage(defaults(), three, 2);
  ASSERT_EQ(got.sets.size(), 3u);
  EXPECT_EQ(got.sets[0].index, two.sets[0].index);
  EXPECT_EQ(got.sets[0].scan, two.sets[0].scan);
  EXPECT_EQ(got.sets[1].index, two.sets[1].index);
  EXPECT_EQ(got.sets[2].index, two.sets[0].index);
  EXPECT_GT(got.sets[1].size(), 0u);
}
