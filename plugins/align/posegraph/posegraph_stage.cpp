// align.posegraph: multi-mission alignment by Scan Context loop closures,
// GICP verification and a jointly optimised pose graph (paper, Sect. III-A).
#include "joint_alignment.hpp"
#include "unposed_stations.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>
#include <lista_alignkit/level.hpp>
#include <lista_alignkit/trajectory_error.hpp>

#include <chrono>
#include <cmath>

namespace lista::align {

using namespace alignkit;  // common/alignkit: clouds, registration, levelling

namespace {

constexpr double kDeg = M_PI / 180.0;

// Every parameter, in its TOML group (JointAlignmentOptions nests them
// otherwise); angles in degrees, as declared. A group whose algorithm's
// options hold just its parameters is those options (scan_context,
// candidates).
struct PoseGraphConfig {
  struct Keyframes {
    double distance = 1.0, angle = 30.0;
    double submap_distance = 2.0;
    int submap_min_points = 8000;
    double submap_max_distance = 10.0, voxel = 0.2;
  } keyframes;
  ScanContextOptions scan_context;
  CandidateOptions candidates;
  RegistrationMethod registration = RegistrationMethod::gicp_gn;
  int icp_iterations = 40;
  struct Closures {
    double coarse_distance = 2.0, fine_distance = 0.5, inlier_distance = 0.3;
    double min_overlap = 0.5, max_rmse = 0.15;
    double consistency_distance = 2.0, consistency_angle = 10.0;
    double sigma_translation = 0.05, sigma_rotation = 0.5;
  } closures;
  bool global_search = true;
  struct Odometry {
    double sigma_translation = 0.02, sigma_rotation = 0.3;
  } odometry;
  struct Scans {
    int neighbours = 2;
    double range = 40.0, ground_clearance = 0.0, voxel = 0.1;
    int points = 15000, map_scans = 3;
    MapUse map_use = MapUse::when_pairs_fail;
    double coarse_distance = 1.0, fine_distance = 0.5, inlier_distance = 0.3, max_plane_rmse = 0.06;
    double sigma_translation = 0.005, sigma_rotation = 0.05;
    bool check_disagreement = true;
    double disagreement = 3.0;
  } scans;
  struct Graph {
    RobustLoss loss = RobustLoss::cauchy;
    double loss_scale = 2.0;
    int iterations = 100;
    bool fix_mission = false;
    int refine_rounds = 1;
    double refine_radius = 3.0;
  } graph;
  LevelConfig level;
};

const ParamTable<PoseGraphConfig>& param_table();

JointAlignmentOptions options_from(const PoseGraphConfig& c) {
  JointAlignmentOptions o;
  const auto& k = c.keyframes;
  o.keyframes.keyframe_distance = k.distance;
  o.keyframes.keyframe_angle = k.angle * kDeg;
  o.keyframes.submap_distance = k.submap_distance;
  o.keyframes.submap_min_points = static_cast<size_t>(k.submap_min_points);
  o.keyframes.submap_max_distance = k.submap_max_distance;
  if (k.submap_max_distance < k.submap_distance)
    throw Error("keyframes.submap_max_distance must be at least keyframes.submap_distance");
  o.keyframes.voxel = k.voxel;
  o.keyframes.scan_context = c.scan_context;
  if (c.scan_context.max_height <= c.scan_context.min_height)
    throw Error("scan_context.max_height must be above scan_context.min_height");
  o.candidates = c.candidates;
  const auto& cl = c.closures;
  o.verify.registration.method = c.registration;
  o.verify.registration.voxel = k.voxel;
  o.verify.registration.coarse_distance = cl.coarse_distance;
  o.verify.registration.fine_distance = cl.fine_distance;
  o.verify.registration.max_iterations = c.icp_iterations;
  o.verify.registration.inlier_distance = cl.inlier_distance;
  o.verify.min_overlap = cl.min_overlap;
  // Coarse clouds match less tightly than fine ones: refuse early only well below the bar.
  o.verify.registration.min_coarse_overlap = 0.6 * cl.min_overlap;
  o.verify.max_rmse = cl.max_rmse;
  o.global_search = c.global_search;
  o.consistency.distance = cl.consistency_distance;
  o.consistency.angle = cl.consistency_angle * kDeg;
  o.odometry_sigma_translation = c.odometry.sigma_translation;
  o.odometry_sigma_rotation = c.odometry.sigma_rotation * kDeg;
  o.closure_sigma_translation = cl.sigma_translation;
  o.closure_sigma_rotation = cl.sigma_rotation * kDeg;
  o.graph.loss = c.graph.loss;
  o.graph.loss_scale = c.graph.loss_scale;
  o.graph.max_iterations = c.graph.iterations;
  o.fix_reference_mission = c.graph.fix_mission;
  o.refine_rounds = c.graph.refine_rounds;
  o.refine_radius = c.graph.refine_radius;
  const auto& sn = c.scans;
  o.scan_edges.neighbours = sn.neighbours;
  o.scan_edges.max_range = sn.range;
  o.scan_edges.ground_clearance = sn.ground_clearance;
  o.scan_edges.registration = o.verify.registration;
  o.scan_edges.registration.voxel = sn.voxel;
  o.scan_edges.max_points = static_cast<size_t>(sn.points);
  o.scan_edges.map_scans = sn.map_scans;
  o.scan_edges.map_use = sn.map_use;
  o.scan_edges.registration.coarse_distance = sn.coarse_distance;
  o.scan_edges.registration.fine_distance = sn.fine_distance;
  o.scan_edges.registration.inlier_distance = sn.inlier_distance;
  o.scan_edges.registration.min_coarse_overlap = 0.6 * cl.min_overlap;
  o.scan_edges.gates = scan_pair_gates(c.registration, cl.min_overlap, cl.max_rmse, sn.max_plane_rmse);
  o.scan_edges.station_min_overlap = o.global.min_overlap;
  o.scan_edges.sigma_translation = sn.sigma_translation;
  o.scan_edges.sigma_rotation = sn.sigma_rotation * kDeg;
  o.check_scan_disagreement = sn.check_disagreement;
  o.scan_disagreement = sn.disagreement;
  return o;
}

class PoseGraphStage : public Stage {
 public:
  explicit PoseGraphStage(const Params& p) : PoseGraphStage(param_table().read(p)) {}
  explicit PoseGraphStage(const PoseGraphConfig& c) : options_(options_from(c)), level_(c.level) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& missions = in.get<MissionSet>("missions");
    if (const auto before = trajectory_error(missions)) ctx.record("ate_before_m", before->rmse);
    JointAlignmentReport report;
    // Stations without poses are placed one by one, then joined back.
    const StationSplit split = split_unposed_stations(missions);
    for (const std::string& name : split.split)
      ctx.info("mission '" + name + "': poses.txt puts every scan at one place, so each is placed as a station of "
               "its own and joined back");
    JointAlignmentOptions options = options_;
    for (const auto& [m, s] : split.from) options.unposed_station.push_back(s != kWholeMission);
    MissionSet aligned =
        split.split.empty() ? align_missions(missions, options, ctx, report)
                            : join_stations(missions, split, align_missions(split.set, options, ctx, report));
    for (const std::string& w : unplaced_stations_warnings(missions, split, report.linked)) ctx.warn(w);
    level_common_frame(aligned, level_, ctx);
    ctx.record("keyframes", static_cast<double>(report.keyframes));
    ctx.record("submap_distance_m", report.submap_distance);
    ctx.record("candidates", static_cast<double>(report.candidates));
    ctx.record("closures_verified", static_cast<double>(report.verified));
    ctx.record("closures_consistent", static_cast<double>(report.consistent));
    ctx.record("closures_intra", static_cast<double>(report.intra));
    ctx.record("closures_proximity", static_cast<double>(report.proximity));
    ctx.record("closures_global", static_cast<double>(report.global));
    ctx.record("pairs_replaced_by_global", static_cast<double>(report.global_replaced));
    ctx.record("scan_edges", static_cast<double>(report.scan_edges));
    ctx.record("scan_edges_left_out", static_cast<double>(report.scan_edges_left_out));
    ctx.record("scan_map_missions", static_cast<double>(report.scan_map_missions));
    ctx.record("station_missions", static_cast<double>(report.station_missions));
    ctx.record("station_links", static_cast<double>(report.station_links));
    if (report.station_pairs > 0) {
      ctx.record("station_pairs", static_cast<double>(report.station_pairs));
      ctx.record("station_pairs_agreeing", static_cast<double>(report.station_pairs_agreeing));
      ctx.record("station_conflict", report.station_conflict);
    }
    if (report.scan_edges > 0) {
      ctx.record("closure_residual_with_scan_edges_m", report.closure_residual_with_scan_edges);
      ctx.record("closure_residual_without_scan_edges_m", report.closure_residual_without_scan_edges);
    }
    ctx.record("closures", static_cast<double>(report.final_closures));
    ctx.record("initial_cost", report.initial_cost);
    ctx.record("final_cost", report.final_cost);
    if (const auto after = trajectory_error(aligned)) {
      ctx.record("ate_after_m", after->rmse);
      ctx.record("ate_after_max_m", after->max);
      ctx.info("ATE after alignment " + std::to_string(after->rmse) + " m over " +
               std::to_string(after->poses) + " poses");
      if (const std::string w = failed_alignment_warning(*after); !w.empty()) ctx.warn(w);
    }
    return Outputs::of("missions", std::move(aligned));
  }

 private:
  JointAlignmentOptions options_;
  LevelConfig level_;
};

StageInfo posegraph_stage_info() {
  StageInfo s;
  s.name = "align.posegraph";
  s.version = "1.14.0";
  s.summary = "Multi-mission alignment: Scan Context loop closures, GICP verification, joint pose graph (Ceres)";
  s.doc =
      "Aligns the missions into the first one's frame and corrects every scan's pose: Scan Context loop closures "
      "between keyframe submaps verified by GICP, a whole-map search for weakly linked missions, and one Ceres "
      "pose graph of odometry, scan-to-scan edges and closures (between missions of stations: whole-scan "
      "registrations instead; three or more missions of stations are laid out together by their pairs' "
      "whole-map placements); then the common frame is levelled. "
      "Details: docs/alignment.md, \"align.posegraph\".";
  s.inputs = {{"missions", "missions", "missions, each in its own map frame"}};
  s.outputs = {{"missions", "missions", "missions with corrected poses and to_common"}};
  s.params = param_table().specs();
  s.renamed = param_table().renames();
  return s;
}

// The flat names before the groups, accepted until the next release.
void renamed_flat_names(ParamTable<PoseGraphConfig>& t) {
  const std::pair<const char*, const char*> names[] = {
      {"keyframe_distance", "keyframes.distance"}, {"keyframe_angle", "keyframes.angle"},
      {"submap_distance", "keyframes.submap_distance"}, {"submap_min_points", "keyframes.submap_min_points"},
      {"submap_max_distance", "keyframes.submap_max_distance"}, {"voxel", "keyframes.voxel"},
      {"rings", "scan_context.rings"}, {"sectors", "scan_context.sectors"}, {"max_radius", "scan_context.max_radius"},
      {"min_height", "scan_context.min_height"}, {"max_height", "scan_context.max_height"},
      {"neighbours", "candidates.neighbours"}, {"max_descriptor_distance", "candidates.max_descriptor_distance"},
      {"max_candidates_per_pair", "candidates.per_pair"}, {"coarse_distance", "closures.coarse_distance"},
      {"fine_distance", "closures.fine_distance"}, {"inlier_distance", "closures.inlier_distance"},
      {"min_overlap", "closures.min_overlap"}, {"max_rmse", "closures.max_rmse"},
      {"consistency_distance", "closures.consistency_distance"}, {"consistency_angle", "closures.consistency_angle"},
      {"closure_sigma_translation", "closures.sigma_translation"}, {"closure_sigma_rotation", "closures.sigma_rotation"},
      {"odometry_sigma_translation", "odometry.sigma_translation"}, {"odometry_sigma_rotation", "odometry.sigma_rotation"},
      {"loss", "graph.loss"}, {"loss_scale", "graph.loss_scale"}, {"solver_iterations", "graph.iterations"},
      {"fix_reference", "graph.fix_reference"}, {"refine_rounds", "graph.refine_rounds"},
      {"refine_radius", "graph.refine_radius"}, {"scan_edges", "scans.neighbours"}, {"scan_range", "scans.range"},
      {"scan_ground_clearance", "scans.ground_clearance"}, {"scan_voxel", "scans.voxel"}, {"scan_points", "scans.points"},
      {"scan_map", "scans.map_scans"}, {"scan_map_use", "scans.map_use"},
      {"scan_coarse_distance", "scans.coarse_distance"}, {"scan_fine_distance", "scans.fine_distance"},
      {"scan_inlier_distance", "scans.inlier_distance"}, {"scan_max_plane_rmse", "scans.max_plane_rmse"},
      {"scan_sigma_translation", "scans.sigma_translation"}, {"scan_sigma_rotation", "scans.sigma_rotation"}};
  for (const auto& [old_name, new_name] : names) t.renamed(old_name, new_name);
  t.renamed("intra_min_travel", "candidates.intra_min_travel", "candidates.intra", 0.0);
  t.renamed("scan_disagreement", "scans.disagreement", "scans.check_disagreement", 0.0);
}

const ParamTable<PoseGraphConfig>& param_table() {
  using C = PoseGraphConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    using K = C::Keyframes;
    auto keyframes = t.group("keyframes", &C::keyframes);
    keyframes.bind("distance", &K::distance, "trajectory length between keyframes").range(0.05, 100).unit("m");
    keyframes.bind("angle", &K::angle, "turn that also starts a keyframe").range(1, 360).unit("deg");
    keyframes.bind("submap_distance", &K::submap_distance, "path length either side of a keyframe joined into its submap")
        .range(0, 100).unit("m");
    keyframes.bind("submap_min_points", &K::submap_min_points,
                   "while the median submap holds fewer points, all submaps grow by submap_distance, up to "
                   "submap_max_distance; 0: they never grow").range(0, 10000000);
    keyframes.bind("submap_max_distance", &K::submap_max_distance, "the most path either side a sparse submap grows to")
        .range(0, 100).unit("m");
    keyframes.bind("voxel", &K::voxel, "submap downsampling for registration").range(0.01, 5).unit("m");
    using S = ScanContextOptions;
    auto scan_context = t.group("scan_context", &C::scan_context);
    scan_context.bind("rings", &S::rings, "Scan Context rings").range(2, 200);
    scan_context.bind("sectors", &S::sectors, "Scan Context sectors (yaw resolution 360/sectors deg)").range(8, 720);
    scan_context.bind("max_radius", &S::max_radius, "Scan Context radius (80 for open roads, 20-40 indoors)").range(1, 500).unit("m");
    scan_context.bind("min_height", &S::min_height, "lowest point used, relative to the sensor").range(-100, 100).unit("m");
    scan_context.bind("max_height", &S::max_height, "highest point used, relative to the sensor (below indoor ceilings)")
        .range(-100, 100).unit("m");
    using N = CandidateOptions;
    auto candidates = t.group("candidates", &C::candidates);
    candidates.bind("neighbours", &N::neighbours, "ring-key nearest neighbours compared per keyframe").range(1, 1000);
    candidates.bind("max_descriptor_distance", &N::max_descriptor_distance, "Scan Context distance accepted as a candidate")
        .range(0, 1);
    candidates.bind("per_pair", &N::per_pair, "best candidates verified per mission pair").range(1, 1e6);
    candidates.bind("intra", &N::intra, "also loops within a mission");
    candidates.bind("intra_min_travel", &N::intra_min_travel, "trajectory between the two keyframes of such a loop at least this")
        .range(0.1, 1e5).unit("m");
    t.choice("registration", &C::registration, registration_method_names(),
             "registration of every scan, submap and map pair: gicp_gn (ours: GICP by Gauss-Newton), gicp (PCL's "
             "Generalized ICP) or icp (point to point)");
    t.bind("icp_iterations", &C::icp_iterations, "iterations per registration stage").range(1, 1000);
    using L = C::Closures;
    auto closures = t.group("closures", &C::closures);
    closures.bind("coarse_distance", &L::coarse_distance, "max correspondence distance, coarse stage").range(0.05, 50).unit("m");
    closures.bind("fine_distance", &L::fine_distance, "max correspondence distance, fine stage").range(0.01, 10).unit("m");
    closures.bind("inlier_distance", &L::inlier_distance, "distance counted as overlap in the fitness check")
        .range(0.01, 10).unit("m");
    closures.bind("min_overlap", &L::min_overlap,
                  "share of each submap's points with a partner in the other (both ways) to accept a closure").range(0, 1);
    closures.bind("max_rmse", &L::max_rmse,
                  "inlier RMSE above which a closure is refused (and a scan-to-scan edge, but with gicp_gn: "
                  "scans.max_plane_rmse)").range(0.001, 10).unit("m");
    closures.bind("consistency_distance", &L::consistency_distance, "closures of one mission pair agree within this")
        .range(0.01, 100).unit("m");
    closures.bind("consistency_angle", &L::consistency_angle, "and within this rotation").range(0.1, 180).unit("deg");
    closures.bind("sigma_translation", &L::sigma_translation, "std. dev. of a loop closure").range(1e-5, 10).unit("m");
    closures.bind("sigma_rotation", &L::sigma_rotation, "std. dev. of a loop closure").range(1e-4, 90).unit("deg");
    t.bind("global_search", &C::global_search,
           "search the whole maps for a mission that no closure links, and check pairs linked by fewer than 4 closures the same way");
    using O = C::Odometry;
    auto odometry = t.group("odometry", &C::odometry);
    odometry.bind("sigma_translation", &O::sigma_translation, "std. dev. of an odometry edge").range(1e-5, 10).unit("m");
    odometry.bind("sigma_rotation", &O::sigma_rotation, "std. dev. of an odometry edge").range(1e-4, 90).unit("deg");
    using G = C::Graph;
    auto graph = t.group("graph", &C::graph);
    graph.choice("loss", &G::loss, {{"cauchy", RobustLoss::cauchy}, {"huber", RobustLoss::huber}, {"none", RobustLoss::none}},
                 "robust loss on loop closures");
    graph.bind("loss_scale", &G::loss_scale, "robust loss scale, in standard deviations").range(0.01, 1000);
    graph.bind("iterations", &G::iterations, "Ceres iterations per solve").range(1, 10000);
    graph.choice("fix_reference", &G::fix_mission, {{"mission", true}, {"first_pose", false}},
                 "gauge: only the first mission's first pose fixed (its drift is corrected too), or the whole "
                 "first mission held as it is (the paper's choice)");
    graph.bind("refine_rounds", &G::refine_rounds, "rounds of proximity closures after the first solve").range(0, 10);
    graph.bind("refine_radius", &G::refine_radius, "keyframes this close in the common frame are tried").range(0.1, 100).unit("m");
    // Declared once for every align.* stage that levels (lista_alignkit/level.hpp).
    bind_level(t, &C::level);
    using E = C::Scans;
    auto scans = t.group("scans", &C::scans);
    scans.bind("neighbours", &E::neighbours,
               "scan-to-scan registrations per scan (onto the next N scans; scan to map gives one per scan); "
               "0: odometry alone").range(0, 10);
    scans.bind("range", &E::range, "points farther from the sensor are left out").range(1, 1000).unit("m");
    scans.bind("ground_clearance", &E::ground_clearance,
               "points lower than this above the scan's ground are left out; 0: the ground is kept").range(0, 10).unit("m");
    scans.bind("voxel", &E::voxel, "finest downsampling").range(0.01, 5).unit("m");
    scans.bind("points", &E::points, "denser scans are downsampled coarser to about this many points").range(100, 1e7);
    scans.bind("map_scans", &E::map_scans,
               "scan to map: each scan registered, in order, onto a local map of this many scans before it "
               "(placed by the registrations before; one edge per scan); 1: never").range(1, 10);
    scans.choice("map_use", &E::map_use,
                 {{"when_pairs_fail", MapUse::when_pairs_fail}, {"always", MapUse::always}, {"never", MapUse::never}},
                 "scan to map per mission: when too few of its scan-to-scan registrations pass, always, or never");
    scans.bind("coarse_distance", &E::coarse_distance, "max correspondence distance, coarse stage").range(0.01, 50).unit("m");
    scans.bind("fine_distance", &E::fine_distance, "max correspondence distance, fine stage").range(0.01, 10).unit("m");
    scans.bind("inlier_distance", &E::inlier_distance, "distance counted as overlap").range(0.01, 10).unit("m");
    scans.bind("max_plane_rmse", &E::max_plane_rmse,
               "with gicp_gn: RMSE along the other scan's local planes above which an edge is refused; raise it for "
               "a scanner noisier than 2 cm").range(0.001, 10).unit("m");
    scans.bind("sigma_translation", &E::sigma_translation,
               "std. dev. of a scan-to-scan edge, horizontal (height and level are left to the odometry)")
        .range(1e-5, 10).unit("m");
    scans.bind("sigma_rotation", &E::sigma_rotation, "std. dev. of a scan-to-scan edge, yaw").range(1e-4, 90).unit("deg");
    scans.bind("check_disagreement", &E::check_disagreement, "scan-to-scan edges that fight the loop closures are left out");
    scans.bind("disagreement", &E::disagreement,
               "edges fight the closures when with them the closures' RMS residual is more than this many times "
               "(and 1 cm more than) without them").at_least(0.0);
    renamed_flat_names(t);
  });
}

}  // namespace

}  // namespace lista::align

LISTA_STAGE_PLUGIN(lista::align::posegraph_stage_info, lista::align::PoseGraphStage)
