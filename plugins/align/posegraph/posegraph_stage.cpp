// align.posegraph: multi-mission alignment by Scan Context loop closures,
// GICP verification and a jointly optimised pose graph (paper, Sect. III-A).
#include "posegraph_stage.hpp"

#include "joint_alignment.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>
#include <lista_alignkit/level.hpp>
#include <lista_alignkit/trajectory_error.hpp>

#include <chrono>
#include <cmath>

namespace lista::align {

namespace {

constexpr double kDeg = M_PI / 180.0;

// Every parameter, flat (JointAlignmentOptions nests them); angles in
// degrees, as declared.
struct PoseGraphConfig {
  double keyframe_distance = 1.0;
  double keyframe_angle = 30.0;
  double submap_distance = 2.0;
  int submap_min_points = 8000;
  double submap_max_distance = 10.0;
  double voxel = 0.2;
  int rings = 20;
  int sectors = 60;
  double max_radius = 40.0;
  double min_height = -3.0;
  double max_height = 1.5;
  int neighbours = 10;
  double max_descriptor_distance = 0.35;
  int max_candidates_per_pair = 200;
  double intra_min_travel = 0.0;
  std::string registration = "gicp_gn";
  double coarse_distance = 2.0;
  double fine_distance = 0.5;
  int icp_iterations = 40;
  double inlier_distance = 0.3;
  double min_overlap = 0.5;
  double max_rmse = 0.15;
  bool global_search = true;
  double consistency_distance = 2.0;
  double consistency_angle = 10.0;
  double odometry_sigma_translation = 0.02;
  double odometry_sigma_rotation = 0.3;
  double closure_sigma_translation = 0.05;
  double closure_sigma_rotation = 0.5;
  std::string loss = "cauchy";
  double loss_scale = 2.0;
  int solver_iterations = 100;
  double level_max_tilt = std::get<double>(level_max_tilt_param().default_value);  // deg
  std::string fix_reference = "first_pose";
  int refine_rounds = 1;
  int scan_edges = 2;
  double scan_range = 40.0;
  double scan_ground_clearance = 0.0;
  double scan_voxel = 0.1;
  int scan_points = 15000;
  int scan_map = 3;
  std::string scan_map_use = "when_pairs_fail";
  double scan_coarse_distance = 1.0;
  double scan_fine_distance = 0.5;
  double scan_inlier_distance = 0.3;
  double scan_max_plane_rmse = 0.06;
  double scan_sigma_translation = 0.005;
  double scan_sigma_rotation = 0.05;
  double scan_disagreement = 3.0;
  double refine_radius = 3.0;
};

const ParamTable<PoseGraphConfig>& param_table();

JointAlignmentOptions options_from(const PoseGraphConfig& c) {
  JointAlignmentOptions o;
  o.keyframes.keyframe_distance = c.keyframe_distance;
  o.keyframes.keyframe_angle = c.keyframe_angle * kDeg;
  o.keyframes.submap_distance = c.submap_distance;
  o.keyframes.submap_min_points = static_cast<size_t>(c.submap_min_points);
  o.keyframes.submap_max_distance = c.submap_max_distance;
  if (o.keyframes.submap_max_distance < o.keyframes.submap_distance)
    throw Error("submap_max_distance must be at least submap_distance");
  o.keyframes.voxel = c.voxel;
  o.keyframes.scan_context.rings = c.rings;
  o.keyframes.scan_context.sectors = c.sectors;
  o.keyframes.scan_context.max_radius = c.max_radius;
  o.keyframes.scan_context.min_z = c.min_height;
  o.keyframes.scan_context.max_z = c.max_height;
  if (o.keyframes.scan_context.max_z <= o.keyframes.scan_context.min_z)
    throw Error("max_height must be above min_height");
  o.candidates.neighbours = c.neighbours;
  o.candidates.max_distance = c.max_descriptor_distance;
  o.candidates.max_per_pair = c.max_candidates_per_pair;
  o.candidates.intra_min_travel = c.intra_min_travel;
  o.verify.registration.method = c.registration;
  o.verify.registration.voxel = o.keyframes.voxel;
  o.verify.registration.coarse_distance = c.coarse_distance;
  o.verify.registration.fine_distance = c.fine_distance;
  o.verify.registration.max_iterations = c.icp_iterations;
  o.verify.registration.inlier_distance = c.inlier_distance;
  o.verify.min_overlap = c.min_overlap;
  // Coarse clouds match less tightly than fine ones: refuse early only well below the bar.
  o.verify.registration.min_coarse_overlap = 0.6 * o.verify.min_overlap;
  o.verify.max_rmse = c.max_rmse;
  o.global_search = c.global_search;
  o.consistency.distance = c.consistency_distance;
  o.consistency.angle = c.consistency_angle * kDeg;
  o.odometry_sigma_translation = c.odometry_sigma_translation;
  o.odometry_sigma_rotation = c.odometry_sigma_rotation * kDeg;
  o.closure_sigma_translation = c.closure_sigma_translation;
  o.closure_sigma_rotation = c.closure_sigma_rotation * kDeg;
  o.graph.loss = c.loss;
  o.graph.loss_scale = c.loss_scale;
  o.graph.max_iterations = c.solver_iterations;
  o.fix_reference_mission = c.fix_reference == "mission";
  o.refine_rounds = c.refine_rounds;
  o.refine_radius = c.refine_radius;
  o.scan_edges.neighbours = c.scan_edges;
  o.scan_edges.max_range = c.scan_range;
  o.scan_edges.ground_clearance = c.scan_ground_clearance;
  o.scan_edges.registration = o.verify.registration;
  o.scan_edges.registration.voxel = c.scan_voxel;
  o.scan_edges.max_points = static_cast<size_t>(c.scan_points);
  o.scan_edges.map_scans = c.scan_map;
  o.scan_edges.map_use = c.scan_map_use == "always" ? MapUse::always
                         : c.scan_map_use == "never" ? MapUse::never
                                                     : MapUse::when_pairs_fail;
  o.scan_edges.registration.coarse_distance = c.scan_coarse_distance;
  o.scan_edges.registration.fine_distance = c.scan_fine_distance;
  o.scan_edges.registration.inlier_distance = c.scan_inlier_distance;
  o.scan_edges.registration.min_coarse_overlap = 0.6 * o.verify.min_overlap;
  o.scan_edges.gates = scan_pair_gates(o.scan_edges.registration.method, o.verify.min_overlap, o.verify.max_rmse,
                                       c.scan_max_plane_rmse);
  o.scan_edges.sigma_translation = c.scan_sigma_translation;
  o.scan_edges.sigma_rotation = c.scan_sigma_rotation * kDeg;
  o.scan_disagreement = c.scan_disagreement;
  return o;
}

class PoseGraphStage : public Stage {
 public:
  explicit PoseGraphStage(const Params& p) : PoseGraphStage(param_table().read(p)) {}
  explicit PoseGraphStage(const PoseGraphConfig& c) : options_(options_from(c)), level_max_tilt_(c.level_max_tilt) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& missions = in.get<MissionSet>("missions");
    if (const auto before = trajectory_error(missions)) ctx.record("ate_before_m", before->rmse);
    JointAlignmentReport report;
    MissionSet aligned = align_missions(missions, options_, ctx, report);
    level_common_frame(aligned, level_max_tilt_, ctx);
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
    Outputs out;
    out.put("missions", std::move(aligned));
    return out;
  }

 private:
  JointAlignmentOptions options_;
  double level_max_tilt_;
};

}  // namespace

StageInfo posegraph_stage_info() {
  StageInfo s;
  s.name = "align.posegraph";
  s.version = "1.8.0";
  s.summary = "Multi-mission alignment: Scan Context loop closures, GICP verification, joint pose graph (Ceres)";
  s.doc =
      "Aligns the missions into the first one's frame and corrects every scan's pose: Scan Context loop closures "
      "between keyframe submaps verified by GICP, a whole-map search for weakly linked missions, and one Ceres "
      "pose graph of odometry, scan-to-scan edges and closures; then the common frame is levelled. "
      "Details: docs/alignment.md, \"align.posegraph\".";
  s.inputs = {{"missions", "missions", "missions, each in its own map frame"}};
  s.outputs = {{"missions", "missions", "missions with corrected poses and to_common"}};
  s.params = param_table().specs();
  return s;
}

namespace {

const ParamTable<PoseGraphConfig>& param_table() {
  using C = PoseGraphConfig;
  static const ParamTable<C> table = [] {
    ParamTable<C> t;
    t.bind("keyframe_distance", &C::keyframe_distance, "trajectory length between keyframes").range(0.05, 100).unit("m");
    t.bind("keyframe_angle", &C::keyframe_angle, "turn that also starts a keyframe").range(1, 360).unit("deg");
    t.bind("submap_distance", &C::submap_distance, "path length either side of a keyframe joined into its submap")
        .range(0, 100).unit("m");
    t.bind("submap_min_points", &C::submap_min_points,
           "while the median keyframe submap holds fewer points, all submaps grow by submap_distance, up to submap_max_distance; 0 = fixed spans")
        .range(0, 10000000);
    t.bind("submap_max_distance", &C::submap_max_distance, "the most path either side a sparse submap grows to")
        .range(0, 100).unit("m");
    t.bind("voxel", &C::voxel, "submap downsampling for registration").range(0.01, 5).unit("m");
    t.bind("rings", &C::rings, "Scan Context rings").range(2, 200);
    t.bind("sectors", &C::sectors, "Scan Context sectors (yaw resolution 360/sectors deg)").range(8, 720);
    t.bind("max_radius", &C::max_radius, "Scan Context radius (80 for open roads, 20-40 indoors)").range(1, 500).unit("m");
    t.bind("min_height", &C::min_height, "lowest point used, relative to the sensor").range(-100, 100).unit("m");
    t.bind("max_height", &C::max_height, "highest point used, relative to the sensor (below indoor ceilings)")
        .range(-100, 100).unit("m");
    t.bind("neighbours", &C::neighbours, "ring-key nearest neighbours compared per keyframe").range(1, 1000);
    t.bind("max_descriptor_distance", &C::max_descriptor_distance, "Scan Context distance accepted as a candidate").range(0, 1);
    t.bind("max_candidates_per_pair", &C::max_candidates_per_pair, "best candidates verified per mission pair").range(1, 1e6);
    t.bind("intra_min_travel", &C::intra_min_travel,
           "loops within a mission: trajectory between the two keyframes at least this (0: none)")
        .range(0, 1e5).unit("m");
    t.bind("registration", &C::registration,
           "registration of every scan, submap and map pair: gicp_gn (ours: GICP by Gauss-Newton), gicp (PCL's Generalized ICP) or icp (point to point)").one_of({"gicp", "gicp_gn", "icp"});
    t.bind("coarse_distance", &C::coarse_distance, "max correspondence distance, coarse stage").range(0.05, 50).unit("m");
    t.bind("fine_distance", &C::fine_distance, "max correspondence distance, fine stage").range(0.01, 10).unit("m");
    t.bind("icp_iterations", &C::icp_iterations, "iterations per registration stage").range(1, 1000);
    t.bind("inlier_distance", &C::inlier_distance, "distance counted as overlap in the fitness check").range(0.01, 10).unit("m");
    t.bind("min_overlap", &C::min_overlap, "share of each submap's points with a partner in the other (both ways) to accept a closure").range(0, 1);
    t.bind("max_rmse", &C::max_rmse, "inlier RMSE above which a closure is refused (and a scan-to-scan edge, but with gicp_gn: scan_max_plane_rmse)").range(0.001, 10).unit("m");
    t.bind("global_search", &C::global_search,
           "search the whole maps for a mission that no closure links, and check pairs linked by fewer than 4 closures the same way");
    t.bind("consistency_distance", &C::consistency_distance, "closures of one mission pair agree within this").range(0.01, 100).unit("m");
    t.bind("consistency_angle", &C::consistency_angle, "and within this rotation").range(0.1, 180).unit("deg");
    t.bind("odometry_sigma_translation", &C::odometry_sigma_translation, "std. dev. of an odometry edge").range(1e-5, 10).unit("m");
    t.bind("odometry_sigma_rotation", &C::odometry_sigma_rotation, "std. dev. of an odometry edge").range(1e-4, 90).unit("deg");
    t.bind("closure_sigma_translation", &C::closure_sigma_translation, "std. dev. of a loop closure").range(1e-5, 10).unit("m");
    t.bind("closure_sigma_rotation", &C::closure_sigma_rotation, "std. dev. of a loop closure").range(1e-4, 90).unit("deg");
    t.bind("loss", &C::loss, "robust loss on loop closures").one_of({"cauchy", "huber", "none"});
    t.bind("loss_scale", &C::loss_scale, "robust loss scale, in standard deviations").range(0.01, 1000);
    t.bind("solver_iterations", &C::solver_iterations, "Ceres iterations per solve").range(1, 10000);
    // Declared once for every align.* stage that levels (lista_alignkit/level.hpp).
    t.bind("level_max_tilt", &C::level_max_tilt, "") = level_max_tilt_param();
    t.bind("fix_reference", &C::fix_reference,
           "gauge: only the first mission's first pose fixed (its drift is corrected too), or the whole "
           "first mission held as it is (the paper's choice)")
        .one_of({"mission", "first_pose"});
    t.bind("refine_rounds", &C::refine_rounds, "rounds of proximity closures after the first solve").range(0, 10);
    t.bind("scan_edges", &C::scan_edges,
           "scan-to-scan registrations per scan (onto the next N scans; scan to map gives one per scan); "
           "0: odometry alone")
        .range(0, 10);
    t.bind("scan_range", &C::scan_range, "scan-to-scan: points farther from the sensor are left out").range(1, 1000).unit("m");
    t.bind("scan_ground_clearance", &C::scan_ground_clearance,
           "scan-to-scan: points lower than this above the scan's ground are left out; 0 = keep the ground").range(0, 10).unit("m");
    t.bind("scan_voxel", &C::scan_voxel, "scan-to-scan: finest downsampling").range(0.01, 5).unit("m");
    t.bind("scan_points", &C::scan_points, "scan-to-scan: denser scans are downsampled coarser to about this many points")
        .range(100, 1e7);
    t.bind("scan_map", &C::scan_map,
           "scan-to-map: each scan registered, in order, onto a local map of this many scans before it "
           "(placed by the registrations before; one edge per scan); 1 = never")
        .range(1, 10);
    t.bind("scan_map_use", &C::scan_map_use,
           "scan-to-map per mission: when too few of its scan-to-scan registrations pass, always, or never")
        .one_of({"when_pairs_fail", "always", "never"});
    t.bind("scan_coarse_distance", &C::scan_coarse_distance, "scan-to-scan: max correspondence distance, coarse stage").range(0.01, 50).unit("m");
    t.bind("scan_fine_distance", &C::scan_fine_distance, "scan-to-scan: max correspondence distance, fine stage").range(0.01, 10).unit("m");
    t.bind("scan_inlier_distance", &C::scan_inlier_distance, "scan-to-scan: distance counted as overlap").range(0.01, 10).unit("m");
    t.bind("scan_max_plane_rmse", &C::scan_max_plane_rmse,
           "scan-to-scan with gicp_gn: RMSE along the other scan's local planes above which an edge is refused; raise it for a scanner noisier than 2 cm").range(0.001, 10).unit("m");
    t.bind("scan_sigma_translation", &C::scan_sigma_translation, "std. dev. of a scan-to-scan edge, horizontal (height and level are left to the odometry)").range(1e-5, 10).unit("m");
    t.bind("scan_sigma_rotation", &C::scan_sigma_rotation, "std. dev. of a scan-to-scan edge, yaw")
        .range(1e-4, 90).unit("deg");
    t.bind("scan_disagreement", &C::scan_disagreement,
           "scan-to-scan edges are left out when with them the closures' RMS residual is more than this many times (and 1 cm more than) without them; 0 = always kept")
        .at_least(0.0);
    t.bind("refine_radius", &C::refine_radius, "keyframes this close in the common frame are tried").range(0.1, 100).unit("m");
    return t;
  }();
  return table;
}

}  // namespace

std::unique_ptr<Stage> make_posegraph_stage(const Params& p) { return std::make_unique<PoseGraphStage>(p); }

namespace {

void register_stages(Registrar& r) { r.add(posegraph_stage_info(), make_posegraph_stage); }

}  // namespace

}  // namespace lista::align

LISTA_PLUGIN(lista::align::register_stages)
