// volumetric.openvdb on the synthetic two-room scene, and its agreement with
// volumetric.octomap on the same input.
#include "../octomap/volumetric_octomap.hpp"
#include "vdb_counts.hpp"
#include "volumetric_openvdb.hpp"

#include "../common/expect_volumetric_params.hpp"

#include <lista/basic_context.hpp>
#include <lista_raycast/scene_checks.hpp>
#include <lista_raycast/synthetic_scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>

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

MissionPoints run_stage(std::unique_ptr<Stage> stage, const MissionSet& missions, int threads,
                        BasicContext* out_ctx = nullptr) {
  BasicContext ctx("diff", threads);
  Inputs in;
  in.set("missions", Data::make(missions));
  Outputs o = stage->run(in, ctx);
  if (out_ctx) out_ctx->info = ctx.info;
  return o.at("changes").as<MissionPoints>();
}

Params defaults() { return Params::defaults(volumetric::volumetric_openvdb_info().params); }

}  // namespace

TEST(VolumetricOpenVdb, FindsRemovedAndAddedBoxesOnly) {
  BasicContext ctx;
  const MissionPoints ch = run_stage(volumetric::make_volumetric_openvdb(defaults()), scene(), 2, &ctx);
  ASSERT_EQ(ch.sets.size(), 2u);
  EXPECT_EQ(ch.missions[0], "A");
  const auto all_a = raycast::label_counts(scene().missions[0]);
  const auto all_b = raycast::label_counts(scene().missions[1]);
  auto got_a = raycast::label_counts(ch.sets[0]);
  auto got_b = raycast::label_counts(ch.sets[1]);
  for (const auto& [l, n] : got_a) std::cout << "A label " << l << ": " << n << " of " << all_a.at(l) << "\n";
  for (const auto& [l, n] : got_b) std::cout << "B label " << l << ": " << n << " of " << all_b.at(l) << "\n";
  // The removed box (A) and the added box (B) are found...
  // (Only where a beam of the other mission crossed the voxel; this sparse
  // test scanner, 16 rings 6 deg apart, crosses about 60% of them.)
  EXPECT_GT(got_a[1], 0.5 * all_a.at(1));
  EXPECT_GT(got_b[3], 0.45 * all_b.at(3));
  // ...the box in the room B never saw is unknown, not change...
  EXPECT_EQ(got_a[2], 0u);
  // ...and static structure and the static box stay static.
  EXPECT_LT(got_a[0], 0.002 * all_a.at(0));
  EXPECT_LT(got_b[0], 0.002 * all_b.at(0));
  EXPECT_EQ(got_a[4] + got_b[4], 0u);
  // Statistics are recorded per mission.
  const auto& metrics = ctx.info.metrics.at("diff");
  EXPECT_GT(metrics.at("A.free_voxels"), metrics.at("A.occupied_voxels"));
  EXPECT_GT(metrics.at("B.voxel_visits"), metrics.at("B.rays"));
  EXPECT_EQ(metrics.at("A.changed_points"), static_cast<double>(ch.sets[0].size()));
  EXPECT_GT(metrics.at("B.changed_voxels"), 0.0);
}

TEST(VolumetricOpenVdb, OutputsOriginalPointsInCommonFrame) {
  const MissionPoints ch = run_stage(volumetric::make_volumetric_openvdb(defaults()), scene(), 1);
  const Mission& b = scene().missions[1];
  ASSERT_FALSE(ch.sets[1].empty());
  ch.sets[1].check_consistent();
  for (size_t i = 0; i < ch.sets[1].size(); i += 7) {
    const uint32_t s = ch.sets[1].scan[i], idx = ch.sets[1].index[i];
    const PointSet& src = *b.scans[s].points;
    ASSERT_EQ(src.index[idx], idx);
    const Eigen::Vector3f expect = (b.sensor_to_common(s) * src.xyz[idx].cast<double>()).cast<float>();
    EXPECT_LT((ch.sets[1].xyz[i] - expect).norm(), 1e-4f);
    EXPECT_EQ(ch.sets[1].label[i], src.label[idx]);
    EXPECT_EQ(ch.sets[1].intensity[i], src.intensity[idx]);
  }
}

// Missions A, A2 (a copy of A) and B: A has nothing to tell from A2; A2's
// removed box changed against the next mission only, B's added box against
// the previous one only. Matching relies on these bits to pair an object
// only with a neighbour it changed against.
TEST(VolumetricOpenVdb, EachChangePointNamesTheNeighboursItChangedAgainst) {
  MissionSet three;
  three.missions = {scene().missions[0], scene().missions[0], scene().missions[1]};
  three.missions[1].name = "A2";
  const MissionPoints ch = run_stage(volumetric::make_volumetric_openvdb(defaults()), three, 2);
  ASSERT_EQ(ch.sets.size(), 3u);
  for (const PointSet& s : ch.sets) {
    s.check_consistent();
    EXPECT_EQ(s.changed_against.size(), s.size());
  }
  EXPECT_EQ(ch.sets[0].size(), 0u) << "A and its copy A2 are the same";
  const auto removed = raycast::label_counts(ch.sets[1]), added = raycast::label_counts(ch.sets[2]);
  ASSERT_GT(removed.count(1), 0u);
  ASSERT_GT(added.count(3), 0u);
  for (size_t i = 0; i < ch.sets[1].size(); ++i)
    if (ch.sets[1].label[i] == 1) {
      EXPECT_EQ(ch.sets[1].changed_against[i], changed_against_next);
    }
  for (size_t i = 0; i < ch.sets[2].size(); ++i)
    if (ch.sets[2].label[i] == 3) {
      EXPECT_EQ(ch.sets[2].changed_against[i], changed_against_previous);
    }
  // With B in the middle (A, B, A2), B's added box changed against both.
  three.missions = {scene().missions[0], scene().missions[1], scene().missions[0]};
  three.missions[2].name = "A2";
  const MissionPoints mid = run_stage(volumetric::make_volumetric_openvdb(defaults()), three, 2);
  size_t both = 0, box = 0;
  for (size_t i = 0; i < mid.sets[1].size(); ++i)
    if (mid.sets[1].label[i] == 3) ++box, both += mid.sets[1].changed_against[i] == changed_against_either;
  ASSERT_GT(box, 0u);
  EXPECT_EQ(both, box);
}

TEST(VolumetricOpenVdb, SameResultForAnyThreadCount) {
  const MissionPoints one = run_stage(volumetric::make_volumetric_openvdb(defaults()), scene(), 1);
  const MissionPoints three = run_stage(volumetric::make_volumetric_openvdb(defaults()), scene(), 3);
  for (size_t m = 0; m < 2; ++m) {
    EXPECT_EQ(one.sets[m].scan, three.sets[m].scan);
    EXPECT_EQ(one.sets[m].index, three.sets[m].index);
  }
}

TEST(VolumetricOpenVdb, AgreesWithOctomapBackend) {
  const MissionPoints vdb = run_stage(volumetric::make_volumetric_openvdb(defaults()), scene(), 2);
  const MissionPoints oct = run_stage(
      volumetric::make_volumetric_octomap(Params::defaults(volumetric::volumetric_octomap_info().params)),
      scene(), 2);
  size_t both = 0, either = 0;
  for (size_t m = 0; m < 2; ++m) {
    const auto a = raycast::provenance(vdb.sets[m]), b = raycast::provenance(oct.sets[m]);
    for (const auto& p : a) both += b.count(p);
    either += a.size() + b.size();
  }
  either -= both;
  ASSERT_GT(either, 0u);
  EXPECT_GE(static_cast<double>(both) / either, 0.98) << both << " of " << either;
}

TEST(VolumetricOpenVdb, UnobservedRegionStaysUnknownWithoutNeighbourhood) {
  // Even comparing single voxels, room 2 (never seen in B) yields nothing.
  Params p = defaults();
  p.set("neighbourhood", int64_t{0});
  const MissionPoints ch = run_stage(volumetric::make_volumetric_openvdb(p), scene(), 2);
  for (uint32_t l : ch.sets[0].label) EXPECT_NE(l, 2u);
  EXPECT_GT(ch.sets[0].size(), 0u);
}

TEST(VolumetricOpenVdb, ThresholdAboveClampedRangeFindsNothing) {
  // clamping bounds the probability difference to 0.971 - 0.1192 = 0.85.
  Params p = defaults();
  p.set("change_threshold", 0.9);
  EXPECT_EQ(run_stage(volumetric::make_volumetric_openvdb(p), scene(), 2).total(), 0u);
}

TEST(VolumetricOpenVdb, RejectsBadParametersAndInput) {
  Params p = defaults();
  p.set("prob_hit", 0.4);
  EXPECT_THROW(volumetric::make_volumetric_openvdb(p), Error);
  p = defaults();
  p.set("clamping_min", 0.99);
  try {
    volumetric::make_volumetric_openvdb(p);
    ADD_FAILURE() << "clamping_min above clamping_max accepted";
  } catch (const Error& e) {
    // The values as the user wrote them, not std::to_string's "0.990000".
    EXPECT_NE(std::string(e.what()).find("got 0.99 and 0.971"), std::string::npos) << e.what();
  }
  // One mission cannot be differenced.
  MissionSet one = scene();
  one.missions.resize(1);
  EXPECT_THROW(run_stage(volumetric::make_volumetric_openvdb(defaults()), one, 1), Error);
  // Every declared default is inside its own range.
  for (const ParamSpec& s : volumetric::volumetric_openvdb_info().params) EXPECT_EQ(s.check(s.default_value), "") << s.name;
}

TEST(VolumetricOpenVdb, MaxRangeIsFiniteAndNotNegative) {
  volumetric::testing::expect_max_range_finite_and_not_negative(volumetric::volumetric_openvdb_info());
}

TEST(VolumetricOpenVdb, GrazeHeightReachesTheRayCasting) {
  volumetric::testing::expect_graze_height_shortens_floor_beams(defaults(), [](const Params& p) {
    BasicContext ctx;
    run_stage(volumetric::make_volumetric_openvdb(p), scene(), 2, &ctx);
    return ctx.info.metrics.at("diff").at("A.free_voxels");
  });
}

// The packed counters: hits and misses are kept apart, and each saturates
// at 65535 alone (a mission of more scans than that keeps working).
TEST(VdbCounts, FieldsAddApartAndSaturateAlone) {
  using namespace lista::volumetric;
  int32_t v = counts::pack(0, 0);
  v = counts::add(v, 1, 0);
  v = counts::add(v, 0, 1);
  v = counts::add(v, 0, 1);
  EXPECT_EQ(counts::hits(v), 1u);
  EXPECT_EQ(counts::misses(v), 2u);
  v = counts::add(counts::pack(65534, 7), 5, 1);
  EXPECT_EQ(counts::hits(v), 65535u) << "saturates, does not wrap into the misses";
  EXPECT_EQ(counts::misses(v), 8u);
  v = counts::add(counts::pack(3, 65535), 1, 1);
  EXPECT_EQ(counts::hits(v), 4u) << "a full miss counter does not carry into the hits";
  EXPECT_EQ(counts::misses(v), 65535u);
  EXPECT_EQ(counts::add(v, 70000, 70000), counts::pack(65535, 65535));
}

// Stop-and-go: one scan per mission. The default threshold adapts (one hit
// against one miss is change between them) and finds the removed and added
// boxes without touching the structure; the same threshold given in the
// pipeline is kept and finds nothing (pair_thresholds' warning says why).
TEST(VolumetricOpenVdb, OneScanMissionsShowChangeAtTheDefaults) {
  raycast::SyntheticSceneConfig c;
  c.rings = 64;
  c.columns = 720;
  MissionSet one = raycast::make_synthetic_scene(c);
  for (Mission& m : one.missions) m.scans.resize(1);
  BasicContext ctx;
  const MissionPoints ch = run_stage(volumetric::make_volumetric_openvdb(defaults()), one, 2, &ctx);
  auto got_a = raycast::label_counts(ch.sets[0]);
  auto got_b = raycast::label_counts(ch.sets[1]);
  const auto all_a = raycast::label_counts(one.missions[0]);
  const auto all_b = raycast::label_counts(one.missions[1]);
  EXPECT_GT(got_a[1] + got_b[3], 0.3 * double(all_a.at(1) + all_b.at(3)));
  EXPECT_LT(got_a[0], 0.002 * all_a.at(0));
  EXPECT_LT(got_b[0], 0.002 * all_b.at(0));
  EXPECT_EQ(got_a[4] + got_b[4], 0u);
  Params given = defaults();
  given.set("change_threshold", 0.35);
  EXPECT_EQ(run_stage(volumetric::make_volumetric_openvdb(given), one, 2).total(), 0u);
}
