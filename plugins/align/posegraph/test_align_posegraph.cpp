#include "global_search.hpp"
#include "joint_alignment.hpp"
#include "loop_closures.hpp"
#include "mission_links.hpp"
#include "pose_graph.hpp"
#include "scan_context.hpp"
#include "scan_odometry.hpp"
#include "seen_through.hpp"
#include "station_links.hpp"
#include "station_vote.hpp"
#include "unposed_stations.hpp"

#include <lista/basic_context.hpp>
#include <lista/data.hpp>
#include <lista/parallel.hpp>
#include <lista_alignkit/cloud_ops.hpp>
#include <lista_alignkit/level.hpp>
#include <lista_alignkit/registration.hpp>
#include <lista_alignkit/synthetic_scene.hpp>
#include <lista_alignkit/trajectory_error.hpp>
#include <lista_testing/plugin_stage.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace lista;
using namespace lista::align;
using namespace lista::alignkit;
using namespace lista::alignkit::testing;

namespace {

constexpr double kHallX = 30, kHallY = 20;

Eigen::Isometry3d offset(double x, double y, double z, double yaw_deg) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

// Keyframes every 2 m keep the suite fast; the defaults run on the datasets.
Params light() {
  Params p;
  p.set("keyframes.distance", 2.0);
  return p;
}

Outputs run_stage(const MissionSet& set, BasicContext& ctx, Params params = light()) {
  auto stage = plugin_test::make_stage("align.posegraph", params.values());
  Inputs in;
  in.set("missions", Data::make(set));
  return stage->run(in, ctx);
}

// Two missions around the same hall: the second starts elsewhere on the loop,
// walks 0.4 m to the side, in its own map frame (offset and turned) and with
// odometry drift (0.1 deg/m of yaw, 1% scale).
// Three scans of one point each, every pose the identity (stations
// without poses).
Mission stations_at_the_origin(const std::string& name) {
  Mission m;
  m.name = name;
  m.scans.resize(3);
  auto one_point = std::make_shared<PointSet>();
  one_point->xyz.emplace_back(1.f, 0.f, 0.f);
  for (auto& s : m.scans) s.points = one_point;
  return m;
}

// A floor with `tries` random boxes for x in [-10, x_max], none on the
// route (|y| < 2 m) a test drives along x.
Scene boxes_beside_route(uint32_t seed, double x_max, int tries) {
  Scene scene;
  scene.boxes.push_back({{-60, -60, -0.1}, {60, 60, 0}});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x_of(-10, x_max), y_of(-12, 12), size(0.2, 1.0), height(0.5, 2.5);
  for (int i = 0; i < tries; ++i) {
    const double x = x_of(rng), y = y_of(rng), w = size(rng);
    if (std::abs(y) < 2.0) continue;
    scene.boxes.push_back({{x, y, 0}, {x + w, y + size(rng), height(rng)}});
  }
  return scene;
}

MissionSet drifted_pair() {
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto truth_a = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  const auto truth_b = loop_route(kHallX, kHallY, 4.0, 1.0, 10.3, 0.4);
  MissionSet set;
  set.missions.push_back(make_mission("a", hall, truth_a, truth_a, 1));
  const auto poses_b = drifted(truth_b, 0.1 * M_PI / 180, 0.01, offset(5, -3, 0.2, 40));
  set.missions.push_back(make_mission("b", hall, truth_b, poses_b, 2));
  return set;
}

// Scans k and k + 1 of a route through `hall` by a `rings`-beam sensor, each
// downsampled as align.posegraph's scan-to-scan edges are (0.1 m), and the
// true pose of b in a's frame.
struct ScanPair {
  Cloud a, b;
  Eigen::Isometry3d truth;  // b -> a
};

ScanPair scan_pair(const Scene& hall, const std::vector<Eigen::Isometry3d>& route, int k, std::mt19937& rng,
                   int rings = 16) {
  const size_t i = static_cast<size_t>(k);
  return {voxel_downsample(cast_scan(hall, route[i], 0, rng, rings).xyz, 0.1),
          voxel_downsample(cast_scan(hall, route[i + 1], 1, rng, rings).xyz, 0.1), route[i].inverse() * route[i + 1]};
}

// align.posegraph's scan-to-scan registration settings, Gauss-Newton GICP.
RegistrationOptions scan_options_gn() {
  RegistrationOptions o;
  o.method = RegistrationMethod::gicp_gn;
  o.voxel = 0.1;
  o.coarse_distance = 1.0;
  return o;
}

}  // namespace

TEST(ScanContext, RecoversYawAndSeparatesPlaces) {
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  std::mt19937 rng(3);
  const auto route = loop_route(kHallX, kHallY, 4.0, 0.5, 0.0);
  const PointSet scan = cast_scan(hall, route[10], 0, rng);
  ScanContextOptions o;
  const ScanContext ref = make_scan_context(scan.xyz, o);
  // The same place seen with the sensor turned by 48 degrees.
  const Eigen::Matrix3f turn = Eigen::AngleAxisf(48 * M_PI / 180, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3f> turned;
  for (const auto& p : scan.xyz) turned.push_back(turn.transpose() * p);  // query frame turned +48 deg
  const ScanContextMatch m = compare(ref, make_scan_context(turned, o));
  EXPECT_LT(m.distance, 0.05);
  EXPECT_NEAR(m.yaw * 180 / M_PI, 48.0, 6.0);
  // A place far along the route looks different.
  const PointSet other = cast_scan(hall, route[60], 1, rng);
  EXPECT_GT(compare(ref, make_scan_context(other.xyz, o)).distance, m.distance + 0.1);
  EXPECT_EQ(ref.ring_key.size(), o.rings);
}

TEST(PoseGraph, PullsDriftedChainOntoClosure) {
  // A straight chain of 11 nodes whose odometry says 1 m steps; a closure from
  // the fixed first node says the last is 9.5 m away: the error is spread.
  std::vector<Eigen::Isometry3d> nodes;
  std::vector<PoseGraphEdge> edges;
  for (int i = 0; i <= 10; ++i) nodes.push_back(offset(i, 0, 0, 0));
  for (int i = 0; i < 10; ++i) edges.push_back({size_t(i), size_t(i + 1), offset(1, 0, 0, 0), 0.05, 0.01, false});
  edges.push_back({0, 10, offset(9.5, 0, 0, 0), 0.01, 0.01, true});
  std::vector<bool> fixed(nodes.size(), false);
  fixed[0] = true;
  PoseGraphOptions o;
  o.loss = RobustLoss::none;
  const PoseGraphSummary s = optimise_pose_graph(nodes, fixed, edges, o);
  ASSERT_TRUE(s.usable);
  EXPECT_LT(s.final_cost, s.initial_cost);
  EXPECT_NEAR(nodes[10].translation().x(), 9.5, 0.01);
  EXPECT_NEAR(nodes[5].translation().x(), 4.75, 0.02);
  EXPECT_NEAR(nodes[0].translation().x(), 0.0, 1e-12);
}

// An edge's height and level may carry sigmas of their own: one that is
// sure of x and y but loose in height yields there to one sure of both.
TEST(PoseGraph, HeightAndLevelWeighOnTheirOwnSigmas) {
  std::vector<Eigen::Isometry3d> nodes(2, Eigen::Isometry3d::Identity());
  PoseGraphEdge loose_height, sure;
  loose_height.measurement.translation() = Eigen::Vector3d(1.0, 0.0, 0.0);
  loose_height.measurement.linear() = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()).toRotationMatrix();
  loose_height.sigma_translation = sure.sigma_translation = 0.01;
  loose_height.sigma_rotation = sure.sigma_rotation = 0.001;
  loose_height.sigma_height = 1.0;
  loose_height.sigma_tilt = 1.0;
  sure.from = loose_height.from = 0;
  sure.to = loose_height.to = 1;
  sure.measurement.translation() = Eigen::Vector3d(1.0, 0.0, 0.5);
  optimise_pose_graph(nodes, {true, false}, {loose_height, sure}, PoseGraphOptions{});
  EXPECT_NEAR(nodes[1].translation().z(), 0.5, 0.001) << "the height is the sure edge's";
  EXPECT_NEAR(nodes[1].translation().x(), 1.0, 0.001);
  EXPECT_LT(rotation_angle(nodes[1].linear()), 0.001) << "and so is the level";
}

TEST(AlignPosegraph, BringsDriftedMissionBack) {
  const MissionSet set = drifted_pair();
  const auto before = trajectory_error(set);
  ASSERT_TRUE(before);
  EXPECT_GT(before->rmse, 1.0);

  BasicContext ctx("align", 2, 0);
  ctx.min_level = LogLevel::info;
  // Mission a's poses are the truth here: hold all of it (the default holds
  // only its first pose and would share b's drift between the two).
  Params p = light();
  p.set("graph.fix_reference", std::string("mission"));
  const Outputs out = run_stage(set, ctx, p);
  const auto& aligned = out.at("missions").as<MissionSet>();
  ASSERT_EQ(aligned.missions.size(), 2u);
  // Point data is shared, not copied.
  EXPECT_EQ(aligned.missions[1].scans[3].points.get(), set.missions[1].scans[3].points.get());
  EXPECT_TRUE(aligned.missions[0].to_common.isApprox(Eigen::Isometry3d::Identity()));
  const auto after = trajectory_error(aligned);
  ASSERT_TRUE(after);
  EXPECT_LT(after->rmse, 0.05) << "ATE before " << before->rmse;
  // Mission b's map frame was 'offset' from the world: to_common undoes it (up to drift at its start).
  const Eigen::Isometry3d expected = offset(5, -3, 0.2, 40).inverse();
  EXPECT_LT((aligned.missions[1].to_common.translation() - expected.translation()).norm(), 0.1);
  const auto& metrics = ctx.info.metrics["align"];
  EXPECT_GT(metrics.at("closures"), 10.0);
  EXPECT_GT(metrics.at("ate_before_m"), 1.0);
  EXPECT_LT(metrics.at("ate_after_m"), 0.05);
}

TEST(AlignPosegraph, MissionWithoutOverlapIsAnErrorNamingIt) {
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const Scene field = make_field(11);
  const auto route = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  MissionSet set;
  set.missions.push_back(make_mission("hall", hall, route, route, 1));
  set.missions.push_back(make_mission("field", field, route, route, 2));
  BasicContext ctx("align", 2, 0);
  ctx.min_level = LogLevel::info;
  try {
    run_stage(set, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'field'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("links to no other mission"), std::string::npos) << e.what();
  }
}

// Missions of a few scans each, taken at scattered spots of the hall (a
// survey of stations): no two keyframes of different missions stand close
// enough for Scan Context, yet both maps show the whole hall.
MissionSet scattered_pair(int furniture = 40) {
  const Scene hall = make_hall(kHallX, kHallY, furniture, 7);
  const auto loop_a = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  const auto loop_b = loop_route(kHallX, kHallY, 4.0, 1.0, 17.0, 0.6);
  std::vector<Eigen::Isometry3d> truth_a, truth_b, poses_b;
  for (size_t i : {0, 34}) truth_a.push_back(loop_a[i]);
  for (size_t i : {0, 34}) truth_b.push_back(loop_b[i]);
  for (const auto& t : truth_b) poses_b.push_back(offset(6, -4, 0.3, 120) * t);
  MissionSet set;
  set.missions.push_back(make_mission("a", hall, truth_a, truth_a, 1));
  set.missions.push_back(make_mission("b", hall, truth_b, poses_b, 2));
  return set;
}

// The stage run on `set`, its info lines kept in `ctx`: the ATE after it.
double ate_after(const MissionSet& set, BasicContext& ctx) {
  ctx.min_level = LogLevel::info;
  const auto after = trajectory_error(run_stage(set, ctx).at("missions").as<MissionSet>());
  EXPECT_TRUE(after);
  return after ? after->rmse : INFINITY;
}

TEST(AlignPosegraph, FewScanMissionsArePlacedByAWholeMapSearch) {
  const MissionSet set = scattered_pair();
  Params off = light();
  off.set("global_search", false);
  BasicContext quiet("align", 2, 0);
  try {
    run_stage(set, quiet, off);
    FAIL() << "Scan Context alone was expected to find nothing here";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'b' links to no other mission"), std::string::npos) << e.what();
  }

  BasicContext ctx("align", 2, 0);
  const double ate = ate_after(set, ctx);
  EXPECT_LT(ate, 0.05);
  EXPECT_GT(ctx.info.metrics["align"].at("closures_global"), 0.0);
  // A few scans far apart are stations: registered whole onto each other
  // (2 mm), they replace the closures between the two missions.
  EXPECT_GE(ctx.info.metrics["align"].at("station_links"), 1.0);
  EXPECT_EQ(ctx.info.metrics["align"].at("closures"), 0.0);
  EXPECT_LT(ate, 0.01);
  bool warned = false;
  for (const auto& m : ctx.messages)
    warned = warned || m.find("mission 'b' was placed on 'a' by a whole-map search") != std::string::npos;
  EXPECT_TRUE(warned);
}

// Three missions of two stations each: laid out together by their pairs'
// whole-map placements (station_vote.hpp), all three pairs agreeing.
TEST(GlobalSearch, PlacesEveryFewScanMissionOfThree) {
  MissionSet set = scattered_pair();
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto loop_c = loop_route(kHallX, kHallY, 4.0, 1.0, 42.0, -0.5);
  std::vector<Eigen::Isometry3d> truth_c, poses_c;
  for (size_t i : {0, 30}) truth_c.push_back(loop_c[i]);
  for (const auto& t : truth_c) poses_c.push_back(offset(-20, 9, -0.4, -75) * t);
  set.missions.push_back(make_mission("c", hall, truth_c, poses_c, 3));
  BasicContext ctx("align", 2, 0);
  const auto& aligned = run_stage(set, ctx).at("missions").as<MissionSet>();
  const auto after = trajectory_error(aligned);
  ASSERT_TRUE(after);
  EXPECT_LT(after->rmse, 0.05);
  EXPECT_EQ(ctx.info.metrics["align"].at("station_pairs"), 3.0);
  EXPECT_EQ(ctx.info.metrics["align"].at("station_pairs_agreeing"), 3.0);
}

TEST(GlobalSearch, AnEmptyRectangularHallIsRefusedNotGuessed) {
  // Without furniture the hall fits its own map turned by half a turn as
  // well: the search must not pick one of the two.
  const MissionSet set = scattered_pair(0);
  BasicContext ctx("align", 2, 0);
  try {
    run_stage(set, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'b' links to no other mission"), std::string::npos) << e.what();
  }
  // It is the rival that refuses it: without the margin a placement passes.
  const auto kf = make_keyframes(set, KeyframeOptions{}, 2);
  GlobalSearchOptions o;
  EXPECT_FALSE(global_search(kf, 0, 1, o, VerifyOptions{}, 2));
  o.margin = 0.0;
  EXPECT_TRUE(global_search(kf, 0, 1, o, VerifyOptions{}, 2));
}

TEST(GlobalSearch, OverrulesAHalfTurnedIncumbentAndKeepsATrueOne) {
  // What recheck of a weakly linked pair sees: closures that agree on the
  // half-turned fit of the hall (turned about its centre), or on the truth.
  const MissionSet set = scattered_pair();
  const auto kf = make_keyframes(set, KeyframeOptions{}, 2);
  const Eigen::Isometry3d truth = offset(6, -4, 0.3, 120).inverse();
  const Eigen::Isometry3d half_turn =
      offset(kHallX / 2, kHallY / 2, 0, 0) * offset(0, 0, 0, 180) * offset(-kHallX / 2, -kHallY / 2, 0, 0) * truth;
  const auto better = global_search(kf, 0, 1, GlobalSearchOptions{}, VerifyOptions{}, 2, half_turn);
  ASSERT_TRUE(better);
  const Eigen::Vector3d at = set.missions[1].scans[1].pose.translation();
  EXPECT_LT((better->reference_T_query * at - truth * at).norm(), 0.3);
  EXPECT_GT(better->plan_score, 1.1 * better->incumbent_plan_score);
  EXPECT_FALSE(better->closures.empty());
  EXPECT_FALSE(global_search(kf, 0, 1, GlobalSearchOptions{}, VerifyOptions{}, 2, truth));
}

TEST(GlobalSearch, BestPlanViewPlacementUndoesTheMapOffset) {
  const MissionSet set = scattered_pair();
  KeyframeOptions ko;
  const auto kf = make_keyframes(set, ko, 2);
  const auto placements = plan_view_placements(kf, 0, 1, GlobalSearchOptions{}, 2);
  ASSERT_FALSE(placements.empty());
  // b's map is its world turned by 120 deg and moved; the best placement puts it back.
  const Eigen::Isometry3d truth = offset(6, -4, 0.3, 120).inverse();
  const Eigen::Isometry3d& best = placements.front().reference_T_query;
  const Eigen::Vector3d at = set.missions[1].scans[1].pose.translation();
  EXPECT_LT((best * at - truth * at).head<2>().norm(), 0.5);
  EXPECT_LT(rotation_angle(best.linear().transpose() * truth.linear()) * 180 / M_PI, 2.0);
  EXPECT_NEAR(best.translation().z(), truth.translation().z(), 0.2);
  EXPECT_GT(placements.front().plan_score, 0.8);
  for (size_t i = 1; i < placements.size(); ++i)
    EXPECT_LE(placements[i].plan_score, placements[i - 1].plan_score);
}

TEST(AlignPosegraph, SingleMissionPassesThrough) {
  const Scene hall = make_hall(kHallX, kHallY, 10, 7);
  auto route = loop_route(kHallX, kHallY, 4.0, 4.0, 0.0);
  MissionSet set;
  set.missions.push_back(make_mission("only", hall, route, route, 1));
  BasicContext ctx("align", 1, 0);
  const auto& out = run_stage(set, ctx).at("missions").as<MissionSet>();
  ASSERT_EQ(out.missions.size(), 1u);
  EXPECT_TRUE(out.missions[0].to_common.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(out.missions[0].scans[2].pose.isApprox(route[2]));
}

namespace {

// Roll `roll_deg` about x, then pitch `pitch_deg` about y.
Eigen::Isometry3d tilt(double roll_deg, double pitch_deg) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (Eigen::AngleAxisd(roll_deg * M_PI / 180, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(pitch_deg * M_PI / 180, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  return t;
}

double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / M_PI;
}

// Up as the estimator reads it from a 16-ring sensor's scans of a furnished
// hall along its loop, every point put through `frame` first.
LevelEstimate hall_up(const Eigen::Isometry3d& frame) {
  const Scene hall = make_hall(kHallX, kHallY, 30, 5);
  std::mt19937 rng(3);
  UpEstimator est;
  for (const Eigen::Isometry3d& pose : loop_route(kHallX, kHallY, 4.0, 6.0, 0.0)) {
    const PointSet scan = cast_scan(hall, pose, 0, rng);
    for (const Eigen::Vector3f& p : scan.xyz) est.add(frame * pose * p.cast<double>());
  }
  return est.estimate();
}

}  // namespace

TEST(Level, ATiltedHallIsReadFromItsFloorsAndWalls) {
  const LevelEstimate level = hall_up(Eigen::Isometry3d::Identity());
  ASSERT_TRUE(level.determined);
  EXPECT_LT(level.tilt_deg, 0.1);
  const Eigen::Isometry3d t = tilt(4.0, -3.0);
  const LevelEstimate tilted = hall_up(t);
  ASSERT_TRUE(tilted.determined);
  EXPECT_GT(tilted.floor_patches, 100u);
  EXPECT_GT(tilted.wall_patches, 100u);
  EXPECT_LT(degrees_between(tilted.up, t.linear() * Eigen::Vector3d::UnitZ()), 0.15);
  EXPECT_NEAR(tilted.tilt_deg, degrees_between(t.linear() * Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ()), 0.15);
  // The levelling rotation takes that up to z.
  EXPECT_LT(degrees_between(levelling_rotation(tilted.up).linear() * tilted.up, Eigen::Vector3d::UnitZ()), 1e-9);
  // 500 km from zero reads the same: double sums keep a surface's thickness.
  Eigen::Isometry3d far = t;
  far.translation() = Eigen::Vector3d(4e5, -3e5, 120.0);
  const LevelEstimate far_off = hall_up(far);
  ASSERT_TRUE(far_off.determined);
  EXPECT_LT(degrees_between(far_off.up, tilted.up), 0.01);
}

TEST(Level, WallsAloneDecideOnlyWhenTheyFaceTwoWays) {
  // Two walls, no floor, tilted: up is the direction along both. One wall
  // leaves a turn about its normal free: nothing is said.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 10.0), h(0.0, 3.0);
  const Eigen::Isometry3d t = tilt(-5.0, 2.0);
  UpEstimator both, one;
  for (int i = 0; i < 40000; ++i) {
    both.add(t * Eigen::Vector3d(u(rng), 0.0, h(rng)));
    both.add(t * Eigen::Vector3d(0.0, u(rng), h(rng)));
    one.add(t * Eigen::Vector3d(u(rng), 0.0, h(rng)));
  }
  const LevelEstimate e = both.estimate();
  ASSERT_TRUE(e.determined);
  EXPECT_EQ(e.floor_patches, 0u);
  EXPECT_LT(degrees_between(e.up, t.linear() * Eigen::Vector3d::UnitZ()), 0.05);
  EXPECT_FALSE(one.estimate().determined);
}

TEST(Level, LinesAndScatterAreNoPatches) {
  // One ring of a sparse scanner is a line in every cell it crosses; a
  // cloud of scatter has no thin direction. Neither says where up is.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  UpEstimator est;
  for (int i = 0; i < 40000; ++i) est.add(Eigen::Vector3d(10.0 * u(rng), 0.0003 * u(rng), 0.5));  // 100 m, 200 cells
  for (int i = 0; i < 20000; ++i) est.add(Eigen::Vector3d(u(rng), u(rng), u(rng)));
  EXPECT_FALSE(est.estimate().determined);
}

TEST(Level, ANoisyTiltedFloorIsBinnedAgainInItsLevelledFrame) {
  // A dense scanner's floor with 1.5 cm of noise, tilted 5 deg in the
  // frame: cells cut level with the frame take slanted slices of the noisy
  // slab, which lean towards the frame's z. Binned again in the frame the
  // first estimate levels, the cuts run along the floor.
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> x(0.0, 20.0), y(0.0, 15.0), h(0.0, 3.0);
  std::normal_distribution<double> noise(0.0, 0.015);
  const Eigen::Isometry3d t = tilt(4.0, -3.0);
  auto scan = std::make_shared<PointSet>();
  auto put = [&](const Eigen::Vector3d& p) { scan->xyz.push_back((t * p).cast<float>()); };
  for (int i = 0; i < 400000; ++i) put({x(rng), y(rng), noise(rng)});
  for (int i = 0; i < 50000; ++i) {
    put({x(rng), 0.0, h(rng)});
    put({0.0, y(rng), h(rng)});
  }
  MissionSet set;
  set.missions.emplace_back();
  set.missions[0].scans.emplace_back();
  set.missions[0].scans[0].points = scan;
  const Eigen::Vector3d truth = t.linear() * Eigen::Vector3d::UnitZ();
  const LevelEstimate e = estimate_common_up(set);
  ASSERT_TRUE(e.determined);
  EXPECT_LT(degrees_between(e.up, truth), 0.05);
  UpEstimator one_pass;
  for (const Eigen::Vector3f& p : scan->xyz) one_pass.add(p.cast<double>());
  EXPECT_GT(degrees_between(one_pass.estimate().up, truth), 0.1);  // what the second binning is for
}

TEST(AlignPosegraph, ATiltedFirstMissionGivesALevelCommonFrame) {
  // Mission a's map frame tilted by 3.6 deg (a SLAM run started on a
  // slope): without levelling the common frame, taken from a's, is tilted
  // as much; levelled, z is up again.
  MissionSet set = drifted_pair();
  const Eigen::Isometry3d t = tilt(3.0, 2.0);
  for (Scan& s : set.missions[0].scans) s.pose = t * s.pose;
  auto up_error = [&](const MissionSet& out) {  // the world's up, in the common frame
    const Eigen::Isometry3d world_to_common = out.missions[0].to_common * t;
    return degrees_between(world_to_common.linear() * Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitZ());
  };
  BasicContext ctx("align", 2, 0);
  const Outputs levelled = run_stage(set, ctx);
  EXPECT_LT(up_error(levelled.at("missions").as<MissionSet>()), 0.2);
  EXPECT_EQ(ctx.info.metrics["align"].at("levelled"), 1.0);
  EXPECT_NEAR(ctx.info.metrics["align"].at("level_tilt_deg"), 3.6, 0.2);
  const auto after = trajectory_error(levelled.at("missions").as<MissionSet>());
  ASSERT_TRUE(after);
  EXPECT_LT(after->rmse, 0.05);

  Params off = light();
  off.set("level.enabled", false);
  BasicContext ctx_off("align", 2, 0);
  EXPECT_GT(up_error(run_stage(set, ctx_off, off).at("missions").as<MissionSet>()), 3.0);
  // A tilt above level.max_tilt is said and left.
  Params low = light();
  low.set("level.max_tilt", 2.0);
  BasicContext ctx_low("align", 2, 0);
  EXPECT_GT(up_error(run_stage(set, ctx_low, low).at("missions").as<MissionSet>()), 3.0);
  EXPECT_EQ(ctx_low.info.metrics["align"].at("levelled"), 0.0);
  bool warned = false;
  for (const auto& m : ctx_low.messages) warned |= m.find("level.max_tilt") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(CloudOps, LevelledFrameKeepsHeadingOnly) {
  Eigen::Isometry3d pose = offset(1, 2, 3, 30);
  pose.linear() = pose.linear() * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Isometry3d f = levelled_frame(pose);
  EXPECT_TRUE(f.translation().isApprox(pose.translation()));
  EXPECT_NEAR(f.linear()(2, 2), 1.0, 1e-12);
  EXPECT_NEAR(std::atan2(f.linear()(1, 0), f.linear()(0, 0)) * 180 / M_PI, 30.0, 1e-9);
  const Cloud pts = {{0.01f, 0.01f, 0.01f}, {0.02f, 0.02f, 0.02f}, {1.01f, 0.f, 0.f}};
  EXPECT_EQ(voxel_downsample(pts, 0.5).size(), 2u);
  EXPECT_NEAR(rotation_angle(pose.linear()), std::acos((pose.linear().trace() - 1) / 2), 1e-9);
  EXPECT_NEAR(rotation_angle(offset(0, 0, 0, -170).linear()) * 180 / M_PI, 170.0, 1e-9);
  EXPECT_NEAR(rotation_angle(Eigen::Matrix3d::Identity()), 0.0, 1e-12);
}

TEST(LoopClosures, IntraMissionCandidatesOnlyFarBackAlongThePath) {
  // One mission going around the hall twice: the second lap revisits the first.
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  auto route = loop_route(kHallX, kHallY, 4.0, 2.0, 0.0);
  const size_t lap = route.size();
  const auto second = loop_route(kHallX, kHallY, 4.0, 2.0, 1.0, 0.3);
  route.insert(route.end(), second.begin(), second.end());
  MissionSet set;
  set.missions.push_back(make_mission("twice", hall, route, route, 1));
  KeyframeOptions ko;
  ko.keyframe_distance = 2.0;
  const auto kf = make_keyframes(set, ko, 2);
  CandidateOptions co;
  EXPECT_TRUE(find_candidates(kf, 1, co, 2).empty());  // off by default
  co.intra = true;
  const auto found = find_candidates(kf, 1, co, 2);
  ASSERT_FALSE(found.empty());
  for (const auto& c : found) {
    EXPECT_GE(kf[c.query].travelled - kf[c.reference].travelled, 30.0);
    EXPECT_EQ(kf[c.reference].mission, kf[c.query].mission);
  }
  // On the second lap many are true revisits (reference keyframe within 4 m);
  // the symmetric box hall aliases about half of them to the far side, which
  // is why every candidate is verified by GICP before it becomes a closure.
  size_t second_lap = 0, near = 0;
  for (const auto& c : found) {
    if (kf[c.query].scan < lap) continue;
    ++second_lap;
    near += (route[kf[c.reference].scan].translation() - route[kf[c.query].scan].translation()).norm() < 4.0;
  }
  EXPECT_GT(second_lap, lap / 4);
  EXPECT_GE(near * 3, second_lap) << near << " of " << second_lap;
}

// Sparse scans make thin submaps: while the median one holds under
// submap_min_points, every submap grows by submap_distance (one span for
// all, so two submaps compared cover alike), up to submap_max_distance.
TEST(LoopClosures, SparseSubmapsGrowTogetherAlongThePath) {
  const MissionSet set = drifted_pair();
  KeyframeOptions ko;
  ko.keyframe_distance = 2.0;
  const auto fixed = make_keyframes(set, ko, 2);
  std::vector<size_t> sizes;
  for (const auto& k : fixed) {
    EXPECT_EQ(k.submap_distance, ko.submap_distance);
    sizes.push_back(k.submap.size());
  }
  std::sort(sizes.begin(), sizes.end());
  const size_t median = sizes[sizes.size() / 2];

  ko.submap_min_points = median;  // already held: nothing grows
  for (const auto& k : make_keyframes(set, ko, 2)) EXPECT_EQ(k.submap_distance, ko.submap_distance);

  ko.submap_min_points = 2 * median;
  const auto grown = make_keyframes(set, ko, 2);
  ASSERT_EQ(grown.size(), fixed.size());
  const double span = grown.front().submap_distance;
  EXPECT_GT(span, ko.submap_distance);
  EXPECT_LE(span, ko.submap_max_distance);
  std::vector<size_t> grown_sizes;
  for (size_t i = 0; i < grown.size(); ++i) {
    EXPECT_EQ(grown[i].submap_distance, span);
    EXPECT_GE(grown[i].submap.size(), fixed[i].submap.size());
    grown_sizes.push_back(grown[i].submap.size());
  }
  std::sort(grown_sizes.begin(), grown_sizes.end());
  // It stopped at the first span whose median holds enough, or at the cap.
  EXPECT_TRUE(grown_sizes[grown_sizes.size() / 2] >= ko.submap_min_points || span == ko.submap_max_distance);

  ko.submap_min_points = 100 * median;  // never reached: capped
  ko.submap_max_distance = 5.0;
  for (const auto& k : make_keyframes(set, ko, 2)) EXPECT_EQ(k.submap_distance, 4.0);  // 2, 4; 6 is past the cap

  MissionSet short_set = set;  // two scans about 1 m apart a mission: 2 m either side holds each whole
  for (auto& m : short_set.missions) m.scans.resize(2);
  for (const auto& k : make_keyframes(short_set, ko, 2)) EXPECT_EQ(k.submap_distance, 2.0);
}

TEST(AlignPosegraph, ASubmapCapBelowTheSpanIsAnError) {
  try {
    plugin_test::make_stage("align.posegraph", {{"keyframes.submap_max_distance", 1.0}});  // under submap_distance (2 m)
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("keyframes.submap_max_distance must be at least keyframes.submap_distance"), std::string::npos)
        << e.what();
  }
}

TEST(AlignPosegraph, ScanEdgesRemoveAScaleErrorBothMissionsShare) {
  // Both missions' odometry is 2 % too long: closures between them agree with
  // each other and a scaled loop still closes, so only metric scan-to-scan
  // registration sees the error.
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto truth_a = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  const auto truth_b = loop_route(kHallX, kHallY, 4.0, 1.0, 10.3, 0.4);
  MissionSet set;
  set.missions.push_back(make_mission("a", hall, truth_a, drifted(truth_a, 0.0, 0.02, Eigen::Isometry3d::Identity()), 1));
  set.missions.push_back(make_mission("b", hall, truth_b, drifted(truth_b, 0.0, 0.02, offset(5, -3, 0.2, 40)), 2));
  auto ate_with = [&](int scan_edges) {
    BasicContext ctx("align", 2, 0);
    ctx.min_level = LogLevel::warning;
    Params p = light();
    p.set("scans.neighbours", int64_t{scan_edges});
    const auto after = trajectory_error(run_stage(set, ctx, p).at("missions").as<MissionSet>());
    const auto& metrics = ctx.info.metrics["align"];
    EXPECT_EQ(metrics.at("scan_edges") > 0, scan_edges > 0);
    // Right edges agree with the closures: kept, and both residuals said.
    EXPECT_EQ(metrics.at("scan_edges_left_out"), 0.0);
    if (scan_edges > 0) {
      EXPECT_GT(metrics.at("closure_residual_without_scan_edges_m"), 0.0);
      EXPECT_LT(metrics.at("closure_residual_with_scan_edges_m"), 0.05);
    }
    return after ? after->rmse : 1e9;
  };
  const double odometry_only = ate_with(0), with_scans = ate_with(2);
  EXPECT_GT(odometry_only, 0.05);
  EXPECT_LT(with_scans, 0.02);
  EXPECT_LT(with_scans * 10, odometry_only) << "odometry only " << odometry_only << " m, with scans " << with_scans << " m";
}

// Fewer than half of the neighbouring scans registering is said, with both
// causes: sparse scans on correct poses, and poses that are not the scans'.
TEST(AlignPosegraph, FewScanRegistrationsAreSaidWithBothCauses) {
  EXPECT_EQ(scan_edges_warning("b", 3, 7), "");      // too few tried to judge
  EXPECT_EQ(scan_edges_warning("b", 124, 247), "");  // half
  const std::string w = scan_edges_warning("b", 91, 247);
  EXPECT_EQ(w.rfind("mission 'b': only 91 of 247 neighbouring scans register", 0), 0u) << w;
  EXPECT_NE(w.find("16-beam scanner outdoors"), std::string::npos) << w;
  EXPECT_NE(w.find("file-name order"), std::string::npos) << w;

  // In a run: mission b's poses belong to its scans in reverse order; a's
  // are right. Only b is named.
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto truth_a = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  const auto truth_b = loop_route(kHallX, kHallY, 4.0, 1.0, 10.3, 0.4);
  MissionSet set;
  set.missions.push_back(make_mission("a", hall, truth_a, truth_a, 1));
  set.missions.push_back(make_mission("b", hall, truth_b, std::vector<Eigen::Isometry3d>(truth_b.rbegin(), truth_b.rend()), 2));
  BasicContext ctx("align", 2, 0);
  try {
    run_stage(set, ctx);
  } catch (const lista::Error&) {
    // the misplaced poses may also leave b unaligned: the warning came first
  }
  size_t about_a = 0, about_b = 0;
  for (const auto& m : ctx.messages) {
    about_a += m.find("mission 'a': only") != std::string::npos;
    about_b += m.find("mission 'b': only") != std::string::npos;
  }
  EXPECT_EQ(about_a, 0u);
  EXPECT_EQ(about_b, 1u);
}

// Scan-to-scan edges are left out when they raise the closures' residual
// several-fold and by more than a centimetre (measured: a VLP-16 in a hall,
// 0.022 m with them against 0.004 m without; the dense scanners' sets stay
// within a factor of 2).
TEST(AlignPosegraph, ScanEdgesThatFightTheClosuresAreLeftOut) {
  EXPECT_TRUE(scan_edges_disagree(0.022, 0.004, 3.0));
  EXPECT_FALSE(scan_edges_disagree(0.0095, 0.0055, 3.0));  // not several-fold
  EXPECT_FALSE(scan_edges_disagree(0.009, 0.001, 3.0));    // several-fold, but millimetres
  EXPECT_TRUE(scan_edges_disagree(0.05, 0.02, 2.0));
  EXPECT_FALSE(scan_edges_disagree(0.05, 0.02, 3.0));
}

// With three or more missions only a mission whose edges alone bend the
// closures is blamed (measured: hall seed 14 with missions A and C from an
// XT32 and B from a VLP-16: 0.019 m with all edges, 0.003 m without B's).
TEST(AlignPosegraph, OnlyTheMissionWhoseEdgesBendTheClosuresIsBlamed) {
  const double nan = std::nan("");
  EXPECT_EQ(missions_to_blame(0.019, {0.018, 0.003, 0.017}, 3.0), (std::vector<char>{0, 1, 0}));
  EXPECT_EQ(missions_to_blame(0.019, {0.018, nan, 0.003}, 3.0), (std::vector<char>{0, 0, 1}));
  // Every mission's edges biased: no one mission's removal is enough.
  EXPECT_EQ(missions_to_blame(0.015, {0.012, 0.011, 0.013}, 3.0), (std::vector<char>{0, 0, 0}));
  // Two missions: none blamed (the caller leaves out both).
  EXPECT_EQ(missions_to_blame(0.022, {0.004, 0.004}, 3.0), (std::vector<char>{0, 0}));
}

// Left-out edges are tried again onto local maps: a hall's VLP-16 pairs
// register ring onto ring (hall seed 11: closure residual 0.022 m with
// them, 0.004 without), its local maps agree (0.008; ATE 0.026 -> 0.014 m).
TEST(AlignPosegraph, LeftOutMissionsTryLocalMaps) {
  const std::vector<bool> scan_to_scan(3, false);
  // Every mission left out: all that had edges.
  EXPECT_EQ(missions_to_retry_on_maps({1, 0, 1}, {0, 0, 0}, true, scan_to_scan, true), (std::vector<size_t>{0, 2}));
  // One blamed: that one.
  EXPECT_EQ(missions_to_retry_on_maps({1, 1, 1}, {0, 1, 0}, false, scan_to_scan, true), (std::vector<size_t>{1}));
  // Already on local maps (their left-out edges stay out), or maps not allowed: none.
  EXPECT_EQ(missions_to_retry_on_maps({1, 1, 1}, {0, 1, 0}, false, {false, true, false}, true), (std::vector<size_t>{}));
  EXPECT_EQ(missions_to_retry_on_maps({1, 1, 1}, {0, 0, 0}, true, scan_to_scan, false), (std::vector<size_t>{}));
}

TEST(Registration, PreparedCloudsServeManyRegistrationsAtOnce) {
  // Two scans 1 m apart in the hall. Prepared clouds are reused across
  // registrations and threads, so nothing a registration does may change
  // them: after using them the other way round, and from four threads at
  // once, a registration still gives what fresh clouds give.
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto route = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  std::mt19937 rng(5);
  RegistrationOptions o;
  o.voxel = 0.1;
  const Cloud a = voxel_downsample(cast_scan(hall, route[3], 0, rng).xyz, o.voxel);
  const Cloud b = voxel_downsample(cast_scan(hall, route[4], 1, rng).xyz, o.voxel);
  const Eigen::Isometry3d truth = route[3].inverse() * route[4];  // b -> a
  const Eigen::Isometry3d guess = truth * offset(0.15, -0.1, 0.0, 2.0);
  const RegistrationResult once = register_clouds(b, a, guess, o);
  ASSERT_TRUE(once.converged);
  EXPECT_LT((once.transform.translation() - truth.translation()).norm(), 0.02);
  EXPECT_GT(std::min(once.overlap, once.reverse_overlap), 0.5);

  const PreparedCloud pa(a, o), pb(b, o);
  EXPECT_EQ(pa.size(), a.size());
  const RegistrationResult back = register_prepared(pa, pb, guess.inverse(), o);  // a onto b first
  EXPECT_LT((back.transform * once.transform).translation().norm(), 0.02);
  std::vector<RegistrationResult> many(4);
  lista::parallel_for(many.size(), 4, [&](size_t i) { many[i] = register_prepared(pb, pa, guess, o); });
  for (const auto& r : many) {
    EXPECT_TRUE(r.transform.isApprox(once.transform, 1e-9));
    EXPECT_DOUBLE_EQ(r.overlap, once.overlap);
    EXPECT_DOUBLE_EQ(r.reverse_overlap, once.reverse_overlap);
    EXPECT_DOUBLE_EQ(r.inlier_rmse, once.inlier_rmse);
  }
  // Too few points: not converged, no throw.
  EXPECT_FALSE(register_prepared(PreparedCloud(Cloud(5, Eigen::Vector3f::Zero()), o), pa, guess, o).converged);
}

TEST(Registration, GaussNewtonGicpFindsWhatPclsGicpFinds) {
  // The Gauss-Newton GICP (gicp_gn) and PCL's (BFGS) minimise one cost: from
  // the same starts, off by up to 0.4 m and 6 degrees, both reach the truth
  // and each other within a centimetre, with the same fitness gates passed.
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto route = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  std::mt19937 rng(9);
  const RegistrationOptions ours = scan_options_gn();
  RegistrationOptions pcl_gicp = ours;
  pcl_gicp.method = RegistrationMethod::gicp;
  for (int k : {2, 6, 10}) {
    const auto [a, b, truth] = scan_pair(hall, route, k, rng);
    for (const Eigen::Isometry3d& off : {offset(0.4, -0.2, 0.0, 6.0), offset(-0.25, 0.3, 0.05, -4.0)}) {
      const RegistrationResult g = register_clouds(b, a, truth * off, ours);
      const RegistrationResult p = register_clouds(b, a, truth * off, pcl_gicp);
      ASSERT_TRUE(g.converged && p.converged) << "scan " << k;
      EXPECT_LT((g.transform.translation() - truth.translation()).norm(), 0.02) << "scan " << k;
      EXPECT_LT(Eigen::AngleAxisd(g.transform.linear() * truth.linear().transpose()).angle(), 0.5 * M_PI / 180);
      EXPECT_LT((g.transform.translation() - p.transform.translation()).norm(), 0.01) << "scan " << k;
      EXPECT_NEAR(g.overlap, p.overlap, 0.02);
      EXPECT_NEAR(g.inlier_rmse, p.inlier_rmse, 0.005);
    }
  }
}

TEST(Registration, GaussNewtonGicpKeepsRingsOffRings) {
  // Registered from the truth, scan pairs of a 64-ring sensor stay within a
  // millimetre of it (median). A neighbourhood that lies along one ring is a
  // strip, not a patch: given a plane anyway, as PCL's covariances give it,
  // its "normal" lies whichever way noise tips it and rings pull onto rings,
  // farther than that (lista-bench registration: 1.2-1.7 mm at the median).
  const Scene hall = make_hall(kHallX, kHallY, 40, 3);
  const auto route = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  std::mt19937 rng(5);
  std::vector<double> errors;
  for (int k : {1, 4, 7, 10, 13, 16}) {
    const auto [a, b, truth] = scan_pair(hall, route, k, rng, 64);
    const RegistrationResult r = register_clouds(b, a, truth, scan_options_gn());
    ASSERT_TRUE(r.converged) << "scan " << k;
    errors.push_back((r.transform.translation() - truth.translation()).norm());
  }
  std::nth_element(errors.begin(), errors.begin() + 3, errors.end());
  EXPECT_LT(errors[3], 0.001);
}

TEST(Registration, PlaneRmseMeasuresTheFitNotTheRingGaps) {
  // Two 16-ring scans measured where they truly lie (no iteration): every
  // point of one is a ring gap from the other's, so the point-to-point RMSE
  // is large, but along the other scan's planes the distance is the noise.
  // Moved 5 cm off the truth, the plane RMSE grows; a gate on it tells the
  // two apart where the point-to-point one cannot (align.posegraph's scan
  // edges, RegistrationGates).
  const Scene hall = make_hall(kHallX, kHallY, 40, 3);
  const auto route = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  std::mt19937 rng(9);
  RegistrationOptions measure_only = scan_options_gn();
  measure_only.max_iterations = 0;
  measure_only.measure_planes = true;
  const RegistrationGates gates = scan_pair_gates(RegistrationMethod::gicp_gn, 0.5, 0.15, 0.06);  // the stage's defaults
  for (int k : {2, 8, 14}) {
    const auto [a, b, truth] = scan_pair(hall, route, k, rng);
    const RegistrationResult at_truth = register_clouds(b, a, truth, measure_only);
    const RegistrationResult off = register_clouds(b, a, truth * offset(0.05, 0.05, 0.05, 0.0), measure_only);
    EXPECT_GT(at_truth.inlier_rmse, 2.0 * at_truth.plane_rmse) << "scan " << k;
    EXPECT_LT(at_truth.plane_rmse, gates.max_plane_rmse) << "scan " << k;
    EXPECT_GT(off.plane_rmse, at_truth.plane_rmse + 0.015) << "scan " << k;
  }
}

TEST(Registration, ScanPairGatesJudgeEachMethodByItsRmse) {
  // gicp_gn's pairs by the RMSE along planes, the others point to point; a
  // plane bar on a result whose planes were not measured refuses it.
  RegistrationResult r;
  r.converged = true;
  r.overlap = r.reverse_overlap = 0.8;
  r.inlier_rmse = 0.16;  // a sparse scanner's ring gaps
  const Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  const RegistrationGates planes = scan_pair_gates(RegistrationMethod::gicp_gn, 0.5, 0.15, 0.06);
  const RegistrationGates points = scan_pair_gates(RegistrationMethod::gicp, 0.5, 0.15, 0.06);
  EXPECT_FALSE(planes.accept(r, guess, true));  // NaN: not measured
  r.plane_rmse = 0.03;
  EXPECT_TRUE(planes.accept(r, guess, true));
  EXPECT_FALSE(points.accept(r, guess, true));
  r.plane_rmse = 0.07;
  r.inlier_rmse = 0.12;
  EXPECT_FALSE(planes.accept(r, guess, true));
  EXPECT_TRUE(points.accept(r, guess, true));
  EXPECT_TRUE(scan_pair_gates(RegistrationMethod::icp, 0.5, 0.15, 0.06).accept(r, guess, true));
}

TEST(TrajectoryError, ReportsTheRigidFitItUsed) {
  // Every estimate is the truth moved by one transform: no error, and the
  // fit is that transform undone.
  const Scene hall = make_hall(kHallX, kHallY, 10, 7);
  const auto route = loop_route(kHallX, kHallY, 4.0, 4.0, 0.0);
  const Eigen::Isometry3d moved = offset(3, -2, 0.5, 25);
  std::vector<Eigen::Isometry3d> poses;
  for (const auto& p : route) poses.push_back(moved * p);
  MissionSet set;
  set.missions.push_back(make_mission("a", hall, route, poses, 1));
  const auto e = trajectory_error(set);
  ASSERT_TRUE(e);
  EXPECT_LT(e->rmse, 1e-9);
  EXPECT_TRUE(e->fit.isApprox(moved.inverse(), 1e-9));
}

// The ground is left out of scan-to-scan registration: what stays is what
// stands on it, unless too little would stay.
TEST(ScanEdges, AboveGroundKeepsWhatStandsOnTheGround) {
  Cloud scan;
  for (int i = 0; i < 2000; ++i) scan.emplace_back(float(i % 50) * 0.2f, float(i / 50) * 0.2f, -0.7f);  // ground
  for (int i = 0; i < 300; ++i)  // a wall: 10 rows of 30 points, 0.05, 0.20, ... 1.40 m above the ground
    scan.emplace_back(3.0f, float(i % 30) * 0.1f, -0.65f + float(i / 30) * 0.15f);
  Eigen::Isometry3d tilted = Eigen::Isometry3d::Identity();  // the pose levels the sensor frame
  const Cloud above = above_ground(scan, tilted, 0.3);
  EXPECT_EQ(above.size(), 240u);  // the wall's two lowest rows go with the ground
  for (const auto& p : above) EXPECT_GT(p.z(), -0.7f + 0.3f);
  EXPECT_EQ(above_ground(scan, tilted, 0.0).size(), scan.size());  // 0: kept
  const Cloud ground_only(scan.begin(), scan.begin() + 2000);
  EXPECT_EQ(above_ground(ground_only, tilted, 0.3).size(), 2000u);  // nothing would stay: kept whole
  // A sensor mounted upside down (pose turned 180 deg about x): heights are the map's.
  tilted.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  Cloud flipped;
  for (const auto& p : scan) flipped.emplace_back(p.x(), -p.y(), -p.z());
  EXPECT_EQ(above_ground(flipped, tilted, 0.3).size(), above.size());
}

// Two 16-ring scans 2.5 m apart on open ground with a few posts and
// crates, the odometry 15 cm too long: with the ground left out the posts
// and crates still give the step (the edges constrain x, y and yaw only;
// height is the odometry's).
TEST(ScanEdges, GroundLeftOutTheStepIsStillMeasured) {
  Scene scene;
  scene.boxes.push_back({{-60, -60, -0.1}, {60, 60, 0}});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-12, 12), size(0.2, 1.0), height(0.5, 2.5);
  for (int i = 0; i < 14; ++i) {
    const double x = u(rng), y = u(rng), w = size(rng);
    if (std::hypot(x, y) < 3.0) continue;  // not on the route
    scene.boxes.push_back({{x, y, 0}, {x + w, y + size(rng), height(rng)}});
  }
  const std::vector<Eigen::Isometry3d> truth = {offset(0, 0, 0.7, 0), offset(2.5, 0, 0.7, 0)};
  const std::vector<Eigen::Isometry3d> odometry = {truth[0], offset(2.65, 0, 0.7, 0)};
  MissionSet set;
  set.missions.push_back(make_mission("a", scene, truth, odometry, 5));
  for (double clearance : {0.0, 0.3}) {
    ScanEdgeOptions o;
    o.neighbours = 1;
    o.registration.voxel = 0.1;  // the stage's scan-to-scan settings
    o.registration.coarse_distance = 1.0;
    o.gates.min_overlap = 0.0;  // judged here by the step's error, not by the gates
    o.gates.max_rmse = 1.0;
    o.ground_clearance = clearance;
    ScanEdgeReport report;
    const auto edges = scan_registration_edges(set, {0}, o, 1, report);
    ASSERT_EQ(edges.size(), 1u) << "clearance " << clearance;
    const Eigen::Vector3d error = edges[0].measurement.translation() - (truth[0].inverse() * truth[1]).translation();
    EXPECT_LT(error.head<2>().norm(), 0.01) << "clearance " << clearance;
  }
}

// Scan to map: a 16-ring sensor walks 8 scans down an open site with posts
// and crates, its odometry 4 % too long and turning 0.5 degree a step. Each
// scan is registered onto the three before it as the registrations placed
// them: every step is measured within 1.5 cm and 0.15 degree of the truth,
// one edge per scan from the scan before (held scans only). Were the map
// placed by the odometry, each map would carry its 10 cm and 0.5 degree
// errors a step into the steps.
TEST(ScanEdges, ScanToMapMeasuresEveryStep) {
  const Scene scene = boxes_beside_route(11, 30.0, 60);
  std::vector<Eigen::Isometry3d> truth, odometry;
  for (int i = 0; i < 8; ++i) {
    truth.push_back(offset(2.5 * i, 0, 0.7, 0));
    odometry.push_back(offset(2.6 * i, 0, 0.7, 0.5 * i));
  }
  MissionSet set;
  set.missions.push_back(make_mission("a", scene, truth, odometry, 5));
  set.missions[0].scans[4].points = std::make_shared<const PointSet>();  // a dropout: stepped over
  ScanEdgeOptions o;
  o.neighbours = 2;
  o.map_scans = 3;
  o.registration.voxel = 0.1;  // the stage's scan-to-scan settings
  o.registration.coarse_distance = 1.0;
  ScanEdgeOptions ungated = o;
  ungated.map_use = MapUse::always;
  ungated.gates.min_overlap = 0.0;  // judged here by the steps' errors, not by the gates
  ungated.gates.max_rmse = 1.0;
  ScanEdgeReport report;
  const auto edges = scan_registration_edges(set, {0}, ungated, 1, report);
  EXPECT_EQ(report.tried, 6u);  // 7 held scans, one edge each after the first
  EXPECT_EQ(report.pairs_tried[0], 0u);  // always: no scan-to-scan pairs first
  ASSERT_EQ(edges.size(), 6u);
  for (const auto& e : edges) {
    EXPECT_EQ(e.to, e.from == 3 ? 5u : e.from + 1);
    const Eigen::Isometry3d true_step = truth[e.from].inverse() * truth[e.to];
    const Eigen::Isometry3d error = true_step.inverse() * e.measurement;
    EXPECT_LT(error.translation().head<2>().norm(), 0.015) << e.from << " -> " << e.to;
    EXPECT_LT(rotation_angle(error.linear()), 0.15 * M_PI / 180) << e.from << " -> " << e.to;
  }
  // With the gates, these sparse scans (1 degree between points of a ring)
  // fail most pairs: the mission switches to local maps by itself...
  scan_registration_edges(set, {0}, o, 1, report);
  EXPECT_EQ(report.pairs_tried[0], 11u);  // 6 + 5 pairs
  EXPECT_LT(2 * report.pairs_accepted[0], report.pairs_tried[0]);
  EXPECT_TRUE(report.scan_to_map[0]);
  EXPECT_EQ(report.tried_per_mission[0], 6u);
  // ...unless told never to.
  o.map_use = MapUse::never;
  scan_registration_edges(set, {0}, o, 1, report);
  EXPECT_FALSE(report.scan_to_map[0]);
  EXPECT_EQ(report.tried_per_mission[0], 11u);
  EXPECT_EQ(report.accepted_per_mission[0], report.pairs_accepted[0]);
}

// Stop-and-go stations (scans farther apart than their points reach) are
// told from a driving mission by the data alone, and their pairs are
// judged by the stations' overlap gate: here an unreachable scan-pair gate
// and an open station gate, so only the stations' pairs pass. Their edges
// are outside the robust loss (the odometry between stations starts far).
TEST(ScanEdges, StationsAreJudgedOnTheWholeMapOverlap) {
  const Scene scene = boxes_beside_route(5, 40.0, 80);
  std::vector<Eigen::Isometry3d> driving, stations;
  for (int i = 0; i < 6; ++i) driving.push_back(offset(0.5 * i, 0, 0.7, 0));
  for (int i = 0; i < 3; ++i) stations.push_back(offset(12.0 * i, 0, 0.7, 0));
  MissionSet set;
  set.missions.push_back(make_mission("driving", scene, driving, driving, 3));
  set.missions.push_back(make_mission("stations", scene, stations, stations, 4));
  ScanEdgeOptions o;
  o.neighbours = 1;
  o.map_use = MapUse::never;
  o.registration.voxel = 0.1;
  o.registration.coarse_distance = 1.0;
  o.gates.min_overlap = 1.01;  // no pair reaches it
  o.gates.max_rmse = 1.0;
  o.station_min_overlap = 0.0;
  o.registration.min_coarse_overlap = 0.0;
  ScanEdgeReport report;
  const auto edges = scan_registration_edges(set, {0, 6}, o, 1, report);
  EXPECT_FALSE(report.stations[0]) << "0.5 m steps: a driving mission";
  for (const auto& e : edges) EXPECT_FALSE(e.robust) << "a station's edge is not discounted by the robust loss";
  EXPECT_TRUE(report.stations[1]) << "12 m steps, points within about 10 m: stations";
  EXPECT_EQ(report.accepted_per_mission[0], 0u);
  EXPECT_GT(report.accepted_per_mission[1], 0u);
}

// Stations of two missions, placed by the graph 0.15 m and 1.5 deg off (as
// closures between downsampled submaps leave them), are registered whole
// onto each other's nearest stations: each edge measures the true relative
// pose to the scans' accuracy, in height and level too.
TEST(StationLinks, WholeScansMeasureWhatTheClosuresLeftOff) {
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto loop = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  std::vector<Eigen::Isometry3d> truth_a = {loop[0], loop[20], loop[40]}, truth_b;
  for (const auto& t : truth_a) truth_b.push_back(t * offset(2.0, 0.5, 0.0, 35));
  MissionSet set;
  set.missions.push_back(make_mission("a", hall, truth_a, truth_a, 1));
  set.missions.push_back(make_mission("b", hall, truth_b, truth_b, 2));
  Graph g;
  g.offset = {0, 3};
  g.nodes = truth_a;
  const Eigen::Isometry3d closures_error = offset(0.15, -0.1, 0.05, 1.5);
  for (const auto& t : truth_b) g.nodes.push_back(closures_error * t);
  ScanEdgeOptions o;
  o.neighbours = 2;
  o.registration.method = RegistrationMethod::gicp_gn;
  o.registration.voxel = 0.1;
  o.registration.coarse_distance = 1.0;
  o.gates = scan_pair_gates(RegistrationMethod::gicp_gn, 0.5, 0.15, 0.06);
  o.station_min_overlap = 0.3;
  PoseGraphEdge closure_like;
  closure_like.sigma_translation = 0.05;
  closure_like.sigma_rotation = 0.5 * M_PI / 180;
  const StationLinks links = station_link_edges(set, g, {1, 1}, o, closure_like, 2);
  EXPECT_EQ(links.tried, 6u) << "each of b's stations onto a's two nearest";
  ASSERT_GE(links.edges.size(), 2u);
  EXPECT_EQ(links.pairs, (std::set<std::pair<size_t, size_t>>{{0, 1}}));
  for (const auto& e : links.edges) {
    ASSERT_LT(e.from, 3u);
    ASSERT_GE(e.to, 3u);
    const Eigen::Isometry3d truth = truth_a[e.from].inverse() * truth_b[e.to - 3];
    const Eigen::Isometry3d err = truth.inverse() * e.measurement;
    EXPECT_LT(err.translation().norm(), 0.01) << e.from << " -> " << e.to;
    EXPECT_LT(rotation_angle(err.linear()) * 180 / M_PI, 0.1) << e.from << " -> " << e.to;
    EXPECT_FALSE(e.planar) << "nothing else ties the missions in height and level";
    EXPECT_EQ(e.sigma_height, 0.05) << "height and level at the closures' sigmas";
    EXPECT_LT(e.sigma_translation, 0.01);
  }
  EXPECT_TRUE(station_link_edges(set, g, {1, 0}, o, closure_like, 2).edges.empty()) << "b drives: no station links";
}

// Stations that no registration links stand where poses.txt puts them:
// said, naming the mission, when the pairs leave them in several groups.
TEST(ScanEdges, UnlinkedStationsAreSaid) {
  Mission m = stations_at_the_origin("tls");
  EXPECT_TRUE(at_one_place(m)) << "no poses: every station at the origin";
  PoseGraphEdge e;
  e.from = 10;  // graph nodes of this mission start at 10
  e.to = 11;
  const std::string w = unlinked_stations_warning(m, 10, {e});
  EXPECT_NE(w.find("mission 'tls' (stop-and-go stations): its 3 stations fall into 2 groups"), std::string::npos) << w;
  PoseGraphEdge f = e;
  f.from = 11;
  f.to = 12;
  EXPECT_EQ(unlinked_stations_warning(m, 10, {e, f}), "");
  m.scans[1].pose.translation().x() = 12.0;
  EXPECT_FALSE(at_one_place(m));
}

// A mission whose poses.txt puts every scan at one place is cut into one
// station per mission for the alignment and joined back: its frame is its
// first station's, its scan poses where the stations were placed.
TEST(UnposedStations, AreCutIntoStationsAndJoinedBack) {
  MissionSet set;
  const Mission unposed = stations_at_the_origin("tls");
  Mission driving = unposed;
  driving.name = "robot";
  for (size_t i = 0; i < 3; ++i) driving.scans[i].pose = offset(0.5 * double(i), 0, 0, 0);
  set.missions = {driving, unposed};
  set.missions.back().scans.emplace_back();  // a dropout: no station of its own
  const StationSplit split = split_unposed_stations(set);
  ASSERT_EQ(split.set.missions.size(), 4u);
  EXPECT_EQ(split.split, std::vector<std::string>{"tls"});
  EXPECT_EQ(split.set.missions[0].scans.size(), 3u) << "a mission with poses is kept whole";
  EXPECT_EQ(split.set.missions[2].name, "tls/station 2");
  MissionSet aligned = split.set;  // as the alignment would place them
  aligned.missions[0].to_common = offset(1, 0, 0, 0);
  for (size_t k = 0; k < 3; ++k) aligned.missions[1 + k].to_common = offset(10.0 * double(k), 5, 0, 30.0 * double(k));
  const MissionSet joined = join_stations(set, split, aligned);
  ASSERT_EQ(joined.missions.size(), 2u);
  EXPECT_TRUE(joined.missions[0].to_common.isApprox(offset(1, 0, 0, 0)));
  for (size_t k = 0; k < 3; ++k)
    EXPECT_TRUE(joined.missions[1].sensor_to_common(k).isApprox(aligned.missions[1 + k].sensor_to_common(0), 1e-9))
        << "station " << k;
  EXPECT_TRUE(joined.missions[1].scans[0].pose.isApprox(Eigen::Isometry3d::Identity(), 1e-9));
  // Stations the final closures leave unlinked to the first mission are said.
  EXPECT_TRUE(unplaced_stations_warnings(set, split, {1, 1, 1, 1}).empty());
  const auto w = unplaced_stations_warnings(set, split, {1, 1, 0, 1});
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("mission 'tls' (stations without poses): 1 of its 3 stations could not be placed"),
            std::string::npos)
      << w[0];
}

// An empty scan (a sensor dropout, a scan io.missions did not read) is
// stepped over: its neighbours register onto each other, and nothing is
// tried with it.
TEST(ScanEdges, AnEmptyScanIsSteppedOver) {
  const Scene hall = make_hall(kHallX, kHallY, 10, 7);
  const std::vector<Eigen::Isometry3d> route = {offset(4, 4, 1, 0), offset(5, 4, 1, 0), offset(6, 4, 1, 0)};
  MissionSet set;
  set.missions.push_back(make_mission("a", hall, route, route, 5));
  set.missions[0].scans[1].points = std::make_shared<const PointSet>();
  ScanEdgeOptions o;
  o.neighbours = 1;
  o.registration.voxel = 0.1;
  ScanEdgeReport report;
  const auto edges = scan_registration_edges(set, {0}, o, 1, report);
  EXPECT_EQ(report.tried, 1u);
  ASSERT_EQ(edges.size(), 1u);
  EXPECT_EQ(edges[0].from, 0u);
  EXPECT_EQ(edges[0].to, 2u);
}

// Ctrl-C during the scan-to-scan registrations (seconds per mission) stops
// them at once rather than after the whole loop.
TEST(ScanEdges, StopWhenCancelled) {
  const MissionSet set = drifted_pair();
  std::vector<size_t> offsets = {0, set.missions[0].scans.size()};
  ScanEdgeOptions o;
  o.neighbours = 2;
  ScanEdgeReport report;
  std::atomic<int> polls{0};
  EXPECT_THROW(scan_registration_edges(
                   set, offsets, o, 1, report, [&] { return ++polls > 3; }, [] { throw lista::Cancelled(); }),
               lista::Cancelled);
  EXPECT_LT(report.tried, 1u);  // nothing reported: the loop did not finish
  scan_registration_edges(set, offsets, o, 1, report);
  EXPECT_GT(report.tried, 3u);
  ASSERT_EQ(report.tried_per_mission.size(), 2u);
  EXPECT_EQ(report.tried_per_mission[0] + report.tried_per_mission[1], report.tried);
  EXPECT_EQ(report.accepted_per_mission[0] + report.accepted_per_mission[1], report.accepted);
}

// A room that is the same turned by half a turn, with one cabinet in a
// corner: three closures vote for the half-turned fit, one for the true
// one. The count picks the half turn; the whole-map check (the cabinet
// lands on nothing when turned) picks the truth.
TEST(LoopClosures, TheWholeMapsDecideBetweenASymmetricRoomsTwoFits) {
  Cloud room;
  for (float t = -5.f; t <= 5.f; t += 0.1f)
    for (float z = 0.f; z <= 2.f; z += 0.25f) {
      room.emplace_back(t, -4.f, z);
      room.emplace_back(t, 4.f, z);
      if (t >= -4.f && t <= 4.f) {
        room.emplace_back(-5.f, t, z);
        room.emplace_back(5.f, t, z);
      }
    }
  for (float x = 3.5f; x <= 4.5f; x += 0.1f)
    for (float y = 2.5f; y <= 3.5f; y += 0.1f)
      for (float z = 0.f; z <= 1.5f; z += 0.1f) room.emplace_back(x, y, z);  // the cabinet
  std::vector<Keyframe> keyframes(2);
  for (size_t m = 0; m < 2; ++m) {
    keyframes[m].mission = m;
    keyframes[m].frame = Eigen::Isometry3d::Identity();
    keyframes[m].submap = room;
  }
  Eigen::Isometry3d half_turn = Eigen::Isometry3d::Identity();
  half_turn.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Closure> closures(4);
  for (size_t i = 0; i < closures.size(); ++i) {
    closures[i].reference = 0;
    closures[i].query = 1;
    closures[i].reference_T_query = i == 0 ? Eigen::Isometry3d::Identity() : half_turn;
    closures[i].rmse = 0.05;
  }
  ConsistencyOptions o;
  std::vector<AmbiguousPlacement> ambiguous;
  const auto kept = consistent_closures(keyframes, closures, o, &ambiguous);
  ASSERT_EQ(kept.size(), 1u);
  EXPECT_TRUE(kept[0].reference_T_query.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(ambiguous.empty()) << "the cabinet tells the fits apart";
  o.rival_margin = 0.0;  // the count alone
  EXPECT_EQ(consistent_closures(keyframes, closures, o).size(), 3u);

  // Drift: the true fit's best-backed closure (the lowest RMSE among equal
  // support) places the map 0.6 m and 4 degrees off, which the vote still
  // counts as the same fit; its other closures place it exactly. Scored by
  // that one closure the true fit loses to the half turn (whose walls fit);
  // scored by the best of its closures it wins.
  Eigen::Isometry3d drifted = Eigen::Isometry3d::Identity();
  drifted.linear() = Eigen::AngleAxisd(4.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  drifted.translation() = Eigen::Vector3d(0.6, 0.0, 0.0);
  std::vector<Closure> drifting(4);
  for (size_t i = 0; i < drifting.size(); ++i) {
    drifting[i].reference = 0;
    drifting[i].query = 1;
    drifting[i].reference_T_query = i == 0 ? drifted : i == 3 ? half_turn : Eigen::Isometry3d::Identity();
    drifting[i].rmse = i == 0 ? 0.01 : 0.05;
  }
  const auto kept_drifting = consistent_closures(keyframes, drifting, ConsistencyOptions{});
  ASSERT_EQ(kept_drifting.size(), 3u);
  for (const auto& c : kept_drifting) EXPECT_FALSE(c.reference_T_query.isApprox(half_turn));

  // Without the cabinet the room is the same turned: nothing tells the two
  // fits apart, and that is reported (the run then warns) rather than hidden.
  Cloud bare;
  for (const auto& p : room)
    if (std::abs(p.x()) > 4.6f || std::abs(p.y()) > 3.9f) bare.push_back(p);
  for (auto& kf : keyframes) kf.submap = bare;
  ambiguous.clear();
  consistent_closures(keyframes, closures, ConsistencyOptions{}, &ambiguous);
  ASSERT_EQ(ambiguous.size(), 1u);
  EXPECT_EQ(ambiguous[0].reference, 0u);
  EXPECT_EQ(ambiguous[0].query, 1u);
  EXPECT_NEAR(ambiguous[0].turn_deg, 180.0, 1e-6);
  EXPECT_NEAR(ambiguous[0].rival_agreement, ambiguous[0].chosen_agreement, 0.02);
}

// Four single-scan stations (64 beams) of the furnished hall, each in its
// own frame (no poses), and closures that put the pair (0, 1) half a turn
// about the hall's centre. The pair (0, 2) fits best half a turned too (plan
// view 0.66), and no verified placement of it is right. Every other pair is
// placed where the four stations' layout puts it, as the truth has it; the
// hall's half-turned placements agree among themselves too, the furniture
// tells them apart.
TEST(StationVote, TheLayoutOverrulesAWrongPairFit) {
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto loop = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  MissionSet set;
  std::vector<Eigen::Isometry3d> truth;
  for (size_t i : {0, 17, 34, 51}) {
    truth.push_back(loop[i]);
    set.missions.push_back(make_mission("s" + std::to_string(i), hall, {loop[i]}, {Eigen::Isometry3d::Identity()},
                                        uint32_t(i + 1), 64));
  }
  const auto kf = make_keyframes(set, KeyframeOptions{}, 2);
  ASSERT_EQ(kf.size(), 4u);
  const Eigen::Isometry3d half_turn =
      offset(kHallX / 2, kHallY / 2, 0, 0) * offset(0, 0, 0, 180) * offset(-kHallX / 2, -kHallY / 2, 0, 0);
  const Eigen::Isometry3d wrong = truth[0].inverse() * half_turn * truth[1];
  const Closure incumbent{0, 1, kf[0].frame.inverse() * wrong * kf[1].frame, 0.6, 0.05, 0.2};
  const StationVote vote =
      vote_station_placements(kf, {1, 1, 1, 1}, {incumbent}, GlobalSearchOptions{}, VerifyOptions{}, 2, [] {});
  EXPECT_EQ(vote.decided.size(), 6u) << "every pair of stations";
  EXPECT_EQ(vote.registered, 6u) << "each station's three partners: all";
  EXPECT_EQ(vote.pairs, 6u);
  EXPECT_EQ(vote.kept, 5u) << "all but (0, 2), which has no right placement";
  std::set<std::pair<size_t, size_t>> placed;
  for (const Closure& c : vote.closures) {
    const size_t a = kf[c.reference].mission, b = kf[c.query].mission;
    placed.insert({a, b});
    const Eigen::Isometry3d err = (truth[a].inverse() * truth[b]).inverse() * implied_map_transform(kf, c);
    EXPECT_LT(err.translation().norm(), 0.1) << a << " -> " << b;
    EXPECT_LT(rotation_angle(err.linear()) * 180 / M_PI, 0.5) << a << " -> " << b;
  }
  EXPECT_TRUE(placed.count({0, 1})) << "the pair the closures got wrong is placed as the truth has it";
  EXPECT_FALSE(placed.count({0, 2})) << "its best fit, half a turn off, is left out";
  const auto alone = global_search(kf, 0, 2, GlobalSearchOptions{}, VerifyOptions{}, 2);
  ASSERT_TRUE(alone) << "on its own the pair would be placed";
  EXPECT_GT(rotation_angle((truth[0].inverse() * truth[2]).linear().transpose() * alone->reference_T_query.linear()),
            M_PI / 2)
      << "... half a turn off";
  EXPECT_FALSE(layout_is_a_guess(vote));
  StationVote scattered = vote;  // fsc's yard: 2 of 12 pairs agree
  scattered.pairs = 12;
  scattered.kept = 2;
  EXPECT_TRUE(layout_is_a_guess(scattered));
  EXPECT_TRUE(vote_station_placements(kf, {1, 1, 0, 0}, {}, GlobalSearchOptions{}, VerifyOptions{}, 2, [] {})
                  .decided.empty())
      << "two stations make no triangle";
}

// Twenty stations along a 100 m corridor, 5 m apart: a pair fits by plan
// view the better the nearer, and only stations within 15 m share enough to
// register. Each station is registered with its nearest partners until six
// verified or twelve were tried: far pairs are never registered, and where
// the nearest fail (the corridor's ends) only the next few are tried.
TEST(StationVote, EachStationRegistersItsBestPartnersOnly) {
  std::vector<size_t> stations(20);
  for (size_t i = 0; i < stations.size(); ++i) stations[i] = i;
  std::map<std::pair<size_t, size_t>, double> fits;
  for (size_t a = 0; a < stations.size(); ++a)
    for (size_t b = a + 1; b < stations.size(); ++b) fits[{a, b}] = 1.0 / double(b - a);
  std::vector<std::pair<size_t, size_t>> order;
  const auto registered = register_best_partners(stations, fits, 6, [&](const std::pair<size_t, size_t>& key) {
    order.push_back(key);
    return key.second - key.first <= 3;
  });
  EXPECT_EQ(order.size(), registered.size()) << "each pair registered once";
  EXPECT_LT(registered.size(), 120u) << "not every pair (190)";
  for (const auto& [a, b] : registered) EXPECT_LE(b - a, 12u) << a << ", " << b << ": only near partners";
  // Stations 3-16 have three verifying partners either side: nothing
  // further between them.
  for (size_t a = 3; a <= 16; ++a)
    for (size_t b = a + 4; b <= 16; ++b) EXPECT_FALSE(registered.count({a, b})) << a << ", " << b;
  for (size_t a = 0; a + 3 < stations.size(); ++a)
    for (size_t d = 1; d <= 3; ++d) EXPECT_TRUE(registered.count({a, a + d})) << a << " + " << d;
  EXPECT_EQ(order.front(), std::make_pair(size_t(0), size_t(1))) << "best fit first";
  // Station 0 has only three verifying partners: its twelve best are tried.
  for (size_t b = 1; b <= 12; ++b) EXPECT_TRUE(registered.count({0, b})) << b;
  // A pair without a plan-view candidate never is.
  fits.erase({0, 1});
  EXPECT_FALSE(register_best_partners(stations, fits, 6, [](const auto&) { return false; }).count({0, 1}));
}

// Two missions of three stations each, without poses: each station is cut
// out, the six laid out together and joined back, every station where it
// stood.
TEST(AlignPosegraph, UnposedStationsOfTwoMissionsAreLaidOutTogether) {
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto loop = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  MissionSet set;
  for (const auto& [name, stops] : std::vector<std::pair<std::string, std::vector<size_t>>>{
           {"a", {0, 23, 46}}, {"b", {11, 34, 57}}}) {
    std::vector<Eigen::Isometry3d> truth;
    for (size_t i : stops) truth.push_back(loop[i]);
    set.missions.push_back(make_mission(name, hall, truth, std::vector<Eigen::Isometry3d>(3, Eigen::Isometry3d::Identity()),
                                        uint32_t(set.missions.size() + 1), 64));
  }
  BasicContext ctx("align", 2, 0);
  EXPECT_LT(ate_after(set, ctx), 0.05);
  bool voted = false;
  for (const auto& m : ctx.messages) {
    EXPECT_EQ(m.find("could not be placed"), std::string::npos) << m;
    EXPECT_EQ(m.find("the layout is a guess"), std::string::npos) << m;
    voted = voted || m.find("stations laid out together") != std::string::npos;
  }
  EXPECT_TRUE(voted);
}

// A station the layout leaves without any agreeing placement links to no
// other: the error says it was outvoted, not that nothing was verified.
// Two one-scan missions in the hall: of the placements the whole-map
// search verified, a wrong one the plan view (or the closures) chose is
// overruled by what the stations saw through, and a right one is kept.
TEST(StationJudgement, WhatTheStationsSawOverrulesAWrongChoice) {
  const Scene hall = make_hall(kHallX, kHallY, 40, 7);
  const auto loop = loop_route(kHallX, kHallY, 4.0, 1.0, 0.0);
  MissionSet set;
  for (size_t i : {0, 17})
    set.missions.push_back(make_mission("s" + std::to_string(i), hall, {loop[i]}, {Eigen::Isometry3d::Identity()},
                                        uint32_t(i + 1), 64));
  const auto kf = make_keyframes(set, KeyframeOptions{}, 2);
  ASSERT_EQ(kf.size(), 2u);
  const Eigen::Isometry3d truth = (kf[0].frame.inverse() * loop[0].inverse() * loop[17] * kf[1].frame);
  auto right = [&](const Eigen::Isometry3d& a_T_b) {
    const Eigen::Isometry3d err = truth.inverse() * a_T_b;
    return err.translation().norm() < 0.1 && rotation_angle(err.linear()) < 0.5 * M_PI / 180;
  };
  const GlobalSearchOptions o;
  const PlacementSearch search = verified_placements(kf, 0, 1, o, VerifyOptions{}, 2);
  const GlobalPlacement* wrong = nullptr;
  bool found_right = false;
  for (const auto& p : search.verified) {
    if (p.overlap < o.min_overlap) continue;
    if (right(p.reference_T_query))
      found_right = true;
    else if (!wrong && !same_placement(p.reference_T_query, truth, search.query_centre))
      wrong = &p;
  }
  ASSERT_TRUE(found_right);
  ASSERT_TRUE(wrong);
  const StationJudgement overruled = judge_station_placements(kf, 0, 1, search, o, std::nullopt, *wrong);
  EXPECT_TRUE(overruled.overruled);
  ASSERT_TRUE(overruled.choice);
  EXPECT_TRUE(right(overruled.choice->reference_T_query));
  EXPECT_NE(overruled.note.find("saw through"), std::string::npos) << overruled.note;
  const StationJudgement wrong_closures =
      judge_station_placements(kf, 0, 1, search, o, wrong->reference_T_query, std::nullopt);
  EXPECT_TRUE(wrong_closures.overruled);
  ASSERT_TRUE(wrong_closures.choice);
  EXPECT_TRUE(right(wrong_closures.choice->reference_T_query));
  const StationJudgement kept = judge_station_placements(kf, 0, 1, search, o, truth, std::nullopt);
  EXPECT_FALSE(kept.overruled) << kept.note;
  EXPECT_FALSE(kept.choice);
  // Closures that put the maps apart see nothing in front of anything: no
  // whole-map registration agrees with them, so they are not judged.
  const StationJudgement apart = judge_station_placements(kf, 0, 1, search, o, offset(200, 0, 0, 0), std::nullopt);
  EXPECT_FALSE(apart.overruled) << apart.note;
}

TEST(StationVote, AnOutvotedStationIsNamedAsSuch) {
  MissionSet set;
  for (const char* name : {"a", "b", "c"}) {
    Mission m = stations_at_the_origin(name);
    m.scans.resize(1);  // one scan: a station
    set.missions.push_back(m);
  }
  std::vector<Keyframe> kf(3);
  for (size_t m = 0; m < 3; ++m) kf[m].mission = m, kf[m].frame = Eigen::Isometry3d::Identity();
  const std::vector<Closure> closures{{0, 1, offset(2, 0, 0, 0), 0.6, 0.05, 1.0}};
  JointAlignmentReport report;
  report.closures_per_mission = {1, 1, 0};
  report.station_pairs = 3;
  report.station_pairs_agreeing = 1;
  try {
    initial_transforms(set, kf, closures, report);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("station 'c' links to no other: of the stations laid out together (1 of 3 "
                                         "pairs agreeing)"),
              std::string::npos)
        << e.what();
  }
  report.station_pairs = 0;  // not laid out: nothing was verified for it
  try {
    initial_transforms(set, kf, closures, report);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("mission 'c' links to no other mission"), std::string::npos) << e.what();
  }
}
