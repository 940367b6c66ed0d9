// volumetric.openvdb on the synthetic two-room scene (its agreement with
// volumetric.octomap: tests/backends).
#include "vdb_counts.hpp"
#include "volumetric_openvdb.hpp"

#include <lista_testing/expect_volumetric_params.hpp>
#include <lista_testing/memory_cap.hpp>

#include <lista/basic_context.hpp>
#include <lista_raycast/scene_checks.hpp>
#include <lista_raycast/synthetic_scene.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <functional>

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
  // The pair's misfit, and no region of it judged wider: the scene is aligned.
  EXPECT_LT(metrics.at("A.misfit"), 0.02);
  EXPECT_EQ(metrics.at("A.misfit_regions"), 0.0);
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
      EXPECT_EQ(ch.sets[1].changed_against[i] & changed_against_either, changed_against_next);
    }
  for (size_t i = 0; i < ch.sets[2].size(); ++i)
    if (ch.sets[2].label[i] == 3) {
      EXPECT_EQ(ch.sets[2].changed_against[i] & changed_against_either, changed_against_previous);
    }
  // With B in the middle (A, B, A2), B's added box changed against both.
  three.missions = {scene().missions[0], scene().missions[1], scene().missions[0]};
  three.missions[2].name = "A2";
  const MissionPoints mid = run_stage(volumetric::make_volumetric_openvdb(defaults()), three, 2);
  size_t both = 0, box = 0;
  for (size_t i = 0; i < mid.sets[1].size(); ++i)
    if (mid.sets[1].label[i] == 3)
      ++box, both += (mid.sets[1].changed_against[i] & changed_against_either) == changed_against_either;
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

namespace {

// One scan from the origin: a beam along (1, tan az, tan el) for every
// azimuth and elevation (degrees), ending at the x that `hit` gives it,
// with the label it gives.
std::shared_ptr<PointSet> fan_scan(const std::vector<double>& azimuths, const std::vector<double>& elevations,
                                   const std::function<std::pair<double, uint32_t>(const Eigen::Vector3d&)>& hit) {
  auto pts = std::make_shared<PointSet>();
  for (double az : azimuths)
    for (double el : elevations) {
      const Eigen::Vector3d d(1.0, std::tan(az * M_PI / 180.0), std::tan(el * M_PI / 180.0));
      const auto [x, label] = hit(d);
      pts->xyz.push_back((d * x).cast<float>());
      pts->label.push_back(label);
      pts->scan.push_back(0);
      pts->index.push_back(uint32_t(pts->index.size()));
    }
  return pts;
}

// `first`, `first + step`, ... up to `last`.
std::vector<double> steps(double first, double last, double step) {
  std::vector<double> v;
  for (double a = first; a <= last + 1e-9; a += step) v.push_back(a);
  return v;
}

// Towards a wall at x = 5: a person (label 1) at x = 2 when `person`, a
// cabinet (label 2) at x = 3 beside it when `cabinet`.
std::shared_ptr<PointSet> wall_scan(bool person, bool cabinet) {
  return fan_scan(steps(-15, 15, 0.5), steps(-6, 6, 0.5), [&](const Eigen::Vector3d& d) {
    auto inside = [&](double at, double y0, double y1) {
      const Eigen::Vector3d p = d * at;
      return p.y() > y0 && p.y() < y1 && std::abs(p.z()) < 0.4;
    };
    if (person && inside(2.0, -0.6, -0.1)) return std::make_pair(2.0, 1u);
    if (cabinet && inside(3.0, 0.1, 0.7)) return std::make_pair(3.0, 2u);
    return std::make_pair(5.0, 0u);
  });
}

Mission wall_mission(const std::string& name, const std::vector<std::pair<bool, bool>>& scans) {
  Mission m;
  m.name = name;
  for (const auto& [person, cabinet] : scans) {
    Scan s;
    s.points = wall_scan(person, cabinet);
    m.scans.push_back(s);
  }
  return m;
}

}  // namespace

// A person in the first two of four scans of mission A, gone in the others
// (one scan alone would leave the voxels free: 1 hit against 3 misses), and
// a cabinet in all of them; mission B has neither. Both are change against
// B, but A's own later scans saw through the person: dynamic evidence.
TEST(VolumetricOpenVdb, APersonGoneWithinTheMissionIsFlaggedDynamic) {
  MissionSet set;
  set.missions.push_back(wall_mission("A", {{true, true}, {true, true}, {false, true}, {false, true}}));
  set.missions.push_back(wall_mission("B", {{false, false}, {false, false}, {false, false}, {false, false}}));
  BasicContext ctx;
  const MissionPoints ch = run_stage(volumetric::make_volumetric_openvdb(defaults()), set, 2, &ctx);
  std::map<uint32_t, std::pair<size_t, size_t>> by_label;  // label -> (changed, of them seen free)
  const PointSet& a = ch.sets[0];
  for (size_t i = 0; i < a.size(); ++i) {
    auto& [changed, seen_free] = by_label[a.label[i]];
    ++changed;
    seen_free += (a.changed_against[i] & seen_free_in_own_mission) != 0;
  }
  ASSERT_GT(by_label[1].first, 10u) << "the person is change against B";
  ASSERT_GT(by_label[2].first, 10u) << "the cabinet is change against B";
  EXPECT_GT(by_label[1].second, 0.9 * by_label[1].first) << "A's later scans saw through the person";
  EXPECT_EQ(by_label[2].second, 0u) << "the cabinet stood all mission";
  EXPECT_EQ(by_label[0].first, 0u);
  EXPECT_EQ(ctx.info.metrics.at("diff").at("A.seen_free_points"), double(by_label[1].second));
}

namespace {

// Towards a wall at x = 5, beams 0.25 deg apart in azimuth from
// `offset_deg`, 1 deg in elevation; with `pole`, a 1.5 mm pole at x = 3
// (label 3) that only the beam at 0.5 deg hits, so the scans offset by
// 0.1 deg pass beside it through its voxel.
std::shared_ptr<PointSet> pole_scan(double offset_deg, bool pole) {
  return fan_scan(steps(-5 + offset_deg, 5 + offset_deg, 0.25), steps(-6, 6, 1), [&](const Eigen::Vector3d& d) {
    const Eigen::Vector3d at_pole = d * 3.0;
    if (pole && at_pole.y() > 0.0255 && at_pole.y() < 0.0270 && std::abs(at_pole.z()) < 0.3)
      return std::make_pair(3.0, 3u);
    return std::make_pair(5.0, 0u);
  });
}

}  // namespace

// A pole thinner than a voxel stands all through mission A, hit by every
// other scan and passed beside in the rest: as many misses as hits, like
// something gone half the time. But the scans that hit it also saw through
// its voxel: partly filled, so its misses are no dynamic evidence.
TEST(VolumetricOpenVdb, AThinPoleSeenThroughBesideItIsNotDynamic) {
  MissionSet set;
  for (const char* name : {"A", "B"}) {
    Mission m;
    m.name = name;
    for (int k = 0; k < 4; ++k) {
      Scan s;
      s.points = pole_scan(k % 2 ? 0.1 : 0.0, name[0] == 'A');
      m.scans.push_back(s);
    }
    set.missions.push_back(m);
  }
  const MissionPoints ch = run_stage(volumetric::make_volumetric_openvdb(defaults()), set, 2);
  size_t pole = 0, flagged = 0;
  for (size_t i = 0; i < ch.sets[0].size(); ++i)
    if (ch.sets[0].label[i] == 3) ++pole, flagged += (ch.sets[0].changed_against[i] & seen_free_in_own_mission) != 0;
  ASSERT_GT(pole, 5u) << "the pole is change against B";
  EXPECT_EQ(flagged, 0u);
}

namespace {

// In a child whose address space is capped 1 GiB above what it uses: a map
// at the finest documented resolution with one beam 10 000 km long; exits
// 3 with the stage's error on stderr, 0 if there was none.
[[noreturn]] void build_too_big_a_map() {
  test_support::cap_address_space(rlim_t(1) << 30);
  Params fine = defaults();
  fine.set("resolution", 0.005);
  fine.set("max_range", 0.0);
  MissionSet far = scene();
  auto pts = std::make_shared<PointSet>(*far.missions[0].scans[0].points);
  pts->xyz.push_back(Eigen::Vector3f(1e7f, 0, 0));
  pts->label.push_back(0);
  pts->scan.push_back(0);
  pts->index.push_back(uint32_t(pts->index.size()));
  far.missions[0].scans[0].points = pts;
  test_support::exit_3_on_error([&] { run_stage(volumetric::make_volumetric_openvdb(fine), far, 2); });
}

}  // namespace

// A map that would outgrow the memory stops with an error that says what
// to change, not with std::bad_alloc and std::terminate from inside OpenVDB.
TEST(VolumetricOpenVdbDeathTest, AMapOutgrowingTheMemoryIsAClearError) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(build_too_big_a_map(), ::testing::ExitedWithCode(3),
              "mission 'A': its occupancy map outgrows the .* GiB of memory free at resolution 0.005 m \\(its "
              "farthest return is 10000000 m from the sensor");
}
