// align.posegraph: multi-mission alignment by Scan Context loop closures,
// GICP verification and a jointly optimised pose graph (paper, Sect. III-A).
#include "posegraph_stage.hpp"

#include "joint_alignment.hpp"

#include <lista/lista.hpp>
#include <lista_alignkit/level.hpp>
#include <lista_alignkit/trajectory_error.hpp>

#include <chrono>
#include <cmath>

namespace lista::align {

namespace {

constexpr double kDeg = M_PI / 180.0;

JointAlignmentOptions options_from(const Params& p) {
  JointAlignmentOptions o;
  o.keyframes.keyframe_distance = p.get<double>("keyframe_distance");
  o.keyframes.keyframe_angle = p.get<double>("keyframe_angle") * kDeg;
  o.keyframes.submap_distance = p.get<double>("submap_distance");
  o.keyframes.submap_min_points = static_cast<size_t>(p.get<int>("submap_min_points"));
  o.keyframes.submap_max_distance = p.get<double>("submap_max_distance");
  if (o.keyframes.submap_max_distance < o.keyframes.submap_distance)
    throw Error("submap_max_distance must be at least submap_distance");
  o.keyframes.voxel = p.get<double>("voxel");
  o.keyframes.scan_context.rings = p.get<int>("rings");
  o.keyframes.scan_context.sectors = p.get<int>("sectors");
  o.keyframes.scan_context.max_radius = p.get<double>("max_radius");
  o.keyframes.scan_context.min_z = p.get<double>("min_height");
  o.keyframes.scan_context.max_z = p.get<double>("max_height");
  if (o.keyframes.scan_context.max_z <= o.keyframes.scan_context.min_z)
    throw Error("max_height must be above min_height");
  o.candidates.neighbours = p.get<int>("neighbours");
  o.candidates.max_distance = p.get<double>("max_descriptor_distance");
  o.candidates.max_per_pair = p.get<int>("max_candidates_per_pair");
  o.candidates.intra_min_travel = p.get<double>("intra_min_travel");
  o.verify.registration.method = p.get<std::string>("registration");
  o.verify.registration.voxel = o.keyframes.voxel;
  o.verify.registration.coarse_distance = p.get<double>("coarse_distance");
  o.verify.registration.fine_distance = p.get<double>("fine_distance");
  o.verify.registration.max_iterations = p.get<int>("icp_iterations");
  o.verify.registration.inlier_distance = p.get<double>("inlier_distance");
  o.verify.min_overlap = p.get<double>("min_overlap");
  // Coarse clouds match less tightly than fine ones: refuse early only well below the bar.
  o.verify.registration.min_coarse_overlap = 0.6 * o.verify.min_overlap;
  o.verify.max_rmse = p.get<double>("max_rmse");
  o.global_search = p.get<bool>("global_search");
  o.consistency.distance = p.get<double>("consistency_distance");
  o.consistency.angle = p.get<double>("consistency_angle") * kDeg;
  o.odometry_sigma_translation = p.get<double>("odometry_sigma_translation");
  o.odometry_sigma_rotation = p.get<double>("odometry_sigma_rotation") * kDeg;
  o.closure_sigma_translation = p.get<double>("closure_sigma_translation");
  o.closure_sigma_rotation = p.get<double>("closure_sigma_rotation") * kDeg;
  o.graph.loss = p.get<std::string>("loss");
  o.graph.loss_scale = p.get<double>("loss_scale");
  o.graph.max_iterations = p.get<int>("solver_iterations");
  o.fix_reference_mission = p.get<std::string>("fix_reference") == "mission";
  o.refine_rounds = p.get<int>("refine_rounds");
  o.refine_radius = p.get<double>("refine_radius");
  o.scan_edges.neighbours = p.get<int>("scan_edges");
  o.scan_edges.max_range = p.get<double>("scan_range");
  o.scan_edges.ground_clearance = p.get<double>("scan_ground_clearance");
  o.scan_edges.registration = o.verify.registration;
  o.scan_edges.registration.voxel = p.get<double>("scan_voxel");
  o.scan_edges.max_points = static_cast<size_t>(p.get<int>("scan_points"));
  o.scan_edges.map_scans = p.get<int>("scan_map");
  const std::string map_use = p.get<std::string>("scan_map_use");
  o.scan_edges.map_use = map_use == "always" ? MapUse::always
                         : map_use == "never" ? MapUse::never
                                              : MapUse::when_pairs_fail;
  o.scan_edges.registration.coarse_distance = p.get<double>("scan_coarse_distance");
  o.scan_edges.registration.fine_distance = p.get<double>("scan_fine_distance");
  o.scan_edges.registration.inlier_distance = p.get<double>("scan_inlier_distance");
  o.scan_edges.registration.min_coarse_overlap = 0.6 * o.verify.min_overlap;
  o.scan_edges.gates = scan_pair_gates(o.scan_edges.registration.method, o.verify.min_overlap, o.verify.max_rmse,
                                       p.get<double>("scan_max_plane_rmse"));
  o.scan_edges.sigma_translation = p.get<double>("scan_sigma_translation");
  o.scan_edges.sigma_rotation = p.get<double>("scan_sigma_rotation") * kDeg;
  o.scan_disagreement = p.get<double>("scan_disagreement");
  return o;
}

class PoseGraphStage : public Stage {
 public:
  explicit PoseGraphStage(const Params& p) : options_(options_from(p)), level_max_tilt_(p.get<double>("level_max_tilt")) {}

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
      "Keyframes are taken every keyframe_distance metres (or keyframe_angle of turn) of each mission's "
      "trajectory; each gets a local submap (scans within submap_distance of path, in a gravity-levelled "
      "frame; while the median submap holds under submap_min_points, all grow by submap_distance up to "
      "submap_max_distance) and a Scan Context descriptor (max height per ring x sector bin, heights relative to the "
      "sensor in [min_height, max_height] so indoor ceilings do not fill every bin). For every keyframe the "
      "ring keys of each earlier mission (and of its own mission more than intra_min_travel back along the "
      "path, for loops within a mission) are searched with a k-d tree (FLANN); the nearest are compared "
      "under every column shift and the best under max_descriptor_distance becomes a candidate with its "
      "yaw. Candidates are verified by coarse-to-fine GICP between the submaps and refused below "
      "min_overlap (checked both ways, so a floor matched to a floor alone is refused) or above max_rmse; "
      "a vote per mission pair drops closures that disagree with the best supported one. A mission left unlinked, "
      "or a pair linked by fewer than 4 closures, is searched for on the whole maps (global_search): plan views "
      "(what stands 0.3-2.5 m over the ground) correlated over every yaw and offset, the best placements "
      "registered map onto map; one that clearly beats every rival (and the closures' placement) places the "
      "mission, with a warning naming it. Missions are placed by a spanning tree over closures from the first (reference) "
      "mission; a mission without closures is an error naming it. The pose graph holds every mission's "
      "odometry chain (relative poses of consecutive scans from poses.txt), scan-to-scan edges (each scan "
      "registered by GICP, from the odometry guess, onto each of the next scan_edges scans, refused below min_overlap or "
      "above max_rmse (gicp_gn: scan_max_plane_rmse, along planes); in a mission where fewer "
      "than half of those pass (gicp_gn: three quarters; scan_map_use), onto a local map of the scan_map scans before it instead, placed by the "
      "registrations before (the ground left out "
      "with scan_ground_clearance > 0); they constrain horizontal position and yaw: metric steps that remove an odometry scale or heading bias which closures cannot see "
      "when every mission shares it) and the closures under a robust loss; it is solved with Ceres (quaternion "
      "manifold), with the reference mission's first pose (or the whole mission, fix_reference) held. After the first "
      "solve, keyframes that have come close are proposed again (refine_rounds) and verified the same way. "
      "Last, the graph is solved again without the scan-to-scan edges: if with them the closures' RMS residual is "
      "more than scan_disagreement times (and 1 cm more than) without, they disagree with the verified closures and "
      "are left out, with a warning naming whose: with three or more missions only those of a mission whose removal "
      "alone brings the residual down as far (a sparse scanner's mission among dense ones), else all. Those left "
      "out that registered scan to scan are tried again onto local maps (scan_map), kept if they agree. "
      "Output: to_common per mission (anchored at its first scan) and corrected scan poses. Metrics: "
      "keyframes, candidates, closures, closures_global, pairs_replaced_by_global, scan_edges, scan_edges_left_out, scan_map_missions, closure residuals with and without "
      "them, costs, and ATE before/after when every mission has poses_gt.txt.";
  s.inputs = {{"missions", "missions", "missions, each in its own map frame"}};
  s.outputs = {{"missions", "missions", "missions with corrected poses and to_common"}};
  s.params = {
      ParamSpec::real("keyframe_distance", 1.0, "trajectory length between keyframes").range(0.05, 100).unit("m"),
      ParamSpec::real("keyframe_angle", 30.0, "turn that also starts a keyframe").range(1, 360).unit("deg"),
      ParamSpec::real("submap_distance", 2.0, "path length either side of a keyframe joined into its submap")
          .range(0, 100).unit("m"),
      ParamSpec::integer("submap_min_points", 8000, "while the median keyframe submap holds fewer points (after the voxel), all grow by submap_distance, up to submap_max_distance: sparse scans (a Livox outdoors) register loosely on a few; 0 = fixed spans")
          .range(0, 10000000),
      ParamSpec::real("submap_max_distance", 10.0, "the most path either side a sparse submap grows to")
          .range(0, 100).unit("m"),
      ParamSpec::real("voxel", 0.2, "submap downsampling for registration").range(0.01, 5).unit("m"),
      ParamSpec::integer("rings", 20, "Scan Context rings").range(2, 200),
      ParamSpec::integer("sectors", 60, "Scan Context sectors (yaw resolution 360/sectors deg)").range(8, 720),
      ParamSpec::real("max_radius", 40.0, "Scan Context radius (80 for open roads, 20-40 indoors)").range(1, 500).unit("m"),
      ParamSpec::real("min_height", -3.0, "lowest point used, relative to the sensor").range(-100, 100).unit("m"),
      ParamSpec::real("max_height", 1.5, "highest point used, relative to the sensor (below indoor ceilings)")
          .range(-100, 100).unit("m"),
      ParamSpec::integer("neighbours", 10, "ring-key nearest neighbours compared per keyframe").range(1, 1000),
      ParamSpec::real("max_descriptor_distance", 0.35, "Scan Context distance accepted as a candidate").range(0, 1),
      ParamSpec::integer("max_candidates_per_pair", 200, "best candidates verified per mission pair").range(1, 1e6),
      ParamSpec::real("intra_min_travel", 0.0,
                      "loops within a mission: trajectory between the two keyframes at least this (0: none)")
          .range(0, 1e5).unit("m"),
      ParamSpec::text("registration", "gicp_gn", "registration method of every scan, submap and map pair: gicp_gn (ours: GICP by Gauss-Newton, a sparse scanner's one-ring strips given no plane; nearer the truth, and faster, than PCL's), gicp (PCL's Generalized ICP, the default before 1.8.0) or icp (point to point)").one_of({"gicp", "gicp_gn", "icp"}),
      ParamSpec::real("coarse_distance", 2.0, "max correspondence distance, coarse stage").range(0.05, 50).unit("m"),
      ParamSpec::real("fine_distance", 0.5, "max correspondence distance, fine stage").range(0.01, 10).unit("m"),
      ParamSpec::integer("icp_iterations", 40, "iterations per registration stage").range(1, 1000),
      ParamSpec::real("inlier_distance", 0.3, "distance counted as overlap in the fitness check").range(0.01, 10).unit("m"),
      ParamSpec::real("min_overlap", 0.5, "share of each submap's points with a partner in the other (both ways) to accept a closure").range(0, 1),
      ParamSpec::real("max_rmse", 0.15, "inlier RMSE above which a closure is refused (and a scan-to-scan edge, but with gicp_gn: scan_max_plane_rmse)").range(0.001, 10).unit("m"),
      ParamSpec::boolean("global_search", true,
                         "a mission that no Scan Context closure links is searched for on the linked missions' maps: "
                         "plan views correlated over every yaw and offset, the best placements registered map onto "
                         "map; pairs linked by fewer than 4 closures are checked the same way (missions of a few scans "
                         "seldom revisit a spot closely enough for Scan Context)"),
      ParamSpec::real("consistency_distance", 2.0, "closures of one mission pair agree within this").range(0.01, 100).unit("m"),
      ParamSpec::real("consistency_angle", 10.0, "and within this rotation").range(0.1, 180).unit("deg"),
      ParamSpec::real("odometry_sigma_translation", 0.02, "std. dev. of an odometry edge").range(1e-5, 10).unit("m"),
      ParamSpec::real("odometry_sigma_rotation", 0.3, "std. dev. of an odometry edge").range(1e-4, 90).unit("deg"),
      ParamSpec::real("closure_sigma_translation", 0.05, "std. dev. of a loop closure").range(1e-5, 10).unit("m"),
      ParamSpec::real("closure_sigma_rotation", 0.5, "std. dev. of a loop closure").range(1e-4, 90).unit("deg"),
      ParamSpec::text("loss", "cauchy", "robust loss on loop closures").one_of({"cauchy", "huber", "none"}),
      ParamSpec::real("loss_scale", 2.0, "robust loss scale, in standard deviations").range(0.01, 1000),
      ParamSpec::integer("solver_iterations", 100, "Ceres iterations per solve").range(1, 10000),
      level_max_tilt_param(),
      ParamSpec::text("fix_reference", "first_pose",
                      "gauge: only the first mission's first pose fixed (its drift is corrected too), or the whole "
                      "first mission held as it is (the paper's choice)")
          .one_of({"mission", "first_pose"}),
      ParamSpec::integer("refine_rounds", 1, "rounds of proximity closures after the first solve").range(0, 10),
      ParamSpec::integer("scan_edges", 2,
                         "scan-to-scan registrations per scan (onto the next N scans; scan to map gives one per scan); "
                         "0: odometry alone")
          .range(0, 10),
      ParamSpec::real("scan_range", 40.0, "scan-to-scan: points farther from the sensor are left out").range(1, 1000).unit("m"),
      ParamSpec::real("scan_ground_clearance", 0.0,
                      "scan-to-scan: points lower than this above the scan's ground (its 2nd-percentile height) are left "
                      "out (the edges constrain x, y and yaw, which the ground cannot tell; 0.3 took a VLP-16 on an open site "
                      "from 0.16 to 0.10 m); 0 = keep the ground").range(0, 10).unit("m"),
      ParamSpec::real("scan_voxel", 0.1, "scan-to-scan: finest downsampling").range(0.01, 5).unit("m"),
      ParamSpec::integer("scan_points", 15000, "scan-to-scan: denser scans are downsampled coarser to about this many points")
          .range(100, 1e7),
      ParamSpec::integer("scan_map", 3,
                         "scan-to-map: each scan registered, in order, onto a local map of this many scans before it "
                         "(placed by the registrations before; one edge per scan); 1 = never")
          .range(1, 10),
      ParamSpec::text("scan_map_use", "when_pairs_fail",
                      "scan-to-map per mission: when fewer than half (gicp_gn: three quarters) of its scan-to-scan registrations pass (sparse scans, "
                      "a 16-beam scanner outdoors), always, or never")
          .one_of({"when_pairs_fail", "always", "never"}),
      ParamSpec::real("scan_coarse_distance", 1.0, "scan-to-scan: max correspondence distance, coarse stage").range(0.01, 50).unit("m"),
      ParamSpec::real("scan_fine_distance", 0.5, "scan-to-scan: max correspondence distance, fine stage").range(0.01, 10).unit("m"),
      ParamSpec::real("scan_inlier_distance", 0.3, "scan-to-scan: distance counted as overlap").range(0.01, 10).unit("m"),
      ParamSpec::real("scan_max_plane_rmse", 0.06, "scan-to-scan with registration gicp_gn: RMSE of the overlapping points along the other scan's local planes above which an edge is refused (point to point, max_rmse, measures a sparse scanner's ring gaps rather than the fit; gicp and icp keep that); raise it for a scanner noisier than 2 cm").range(0.001, 10).unit("m"),
      ParamSpec::real("scan_sigma_translation", 0.005, "std. dev. of a scan-to-scan edge, horizontal (height and level are left to the odometry)").range(1e-5, 10).unit("m"),
      ParamSpec::real("scan_sigma_rotation", 0.05, "std. dev. of a scan-to-scan edge, yaw")
          .range(1e-4, 90).unit("deg"),
      ParamSpec::real("scan_disagreement", 3.0,
                      "scan-to-scan edges are left out (with a warning) when, solved with them, the final loop closures' "
                      "RMS residual is more than this many times (and 1 cm more than) its value solved without them: they "
                      "disagree with the verified closures (a sparse scanner's rings register ring onto ring); judged per "
                      "mission with three or more; 0 = always kept")
          .at_least(0.0),
      ParamSpec::real("refine_radius", 3.0, "keyframes this close in the common frame are tried").range(0.1, 100).unit("m"),
  };
  return s;
}

std::unique_ptr<Stage> make_posegraph_stage(const Params& p) { return std::make_unique<PoseGraphStage>(p); }

namespace {

void register_stages(Registrar& r) { r.add(posegraph_stage_info(), make_posegraph_stage); }

}  // namespace

}  // namespace lista::align

LISTA_PLUGIN(lista::align::register_stages)
