// match.weighted: the paper's correspondence step (weighted physical +
// descriptor distance, optimal assignment per consecutive mission pair).
#include "weighted_matcher.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>
#include <lista/parallel.hpp>
#include <lista_objreg/icp_refine.hpp>
#include <lista_objreg/surface_share.hpp>
#include <lista_objreg/upright.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace lista::matching {

namespace {

// The matcher's settings and the stage's own: the shape check's registration
// and floor gate.
struct MatchStageConfig : WeightedMatchConfig {
  double shape_voxel = 0.04;      // m
  double shape_distance = 0.05;   // m
  double shape_gap = 0.15;        // m
  double max_lift = 0.15;         // m
  double max_tilt = 20.0;         // deg
  bool upright_poses = true;
  bool corner_hypotheses = true;
};

const ParamTable<MatchStageConfig>& param_table();

class WeightedMatchStage : public Stage {
 public:
  explicit WeightedMatchStage(const Params& p) {
    const MatchStageConfig c = param_table().read(p);
    cfg_ = c;
    max_lift_ = c.max_lift;
    max_tilt_ = c.max_tilt;
    upright_poses_ = c.upright_poses;
    shape_ = registration::shape_check_config(c.shape_voxel, c.shape_distance);
    shape_.corner_hypotheses = c.corner_hypotheses;
    surface_.voxel = shape_.voxel;
    surface_.inlier = shape_.inlier_distance;
    surface_.gap = c.shape_gap;
    surface_.max_points = shape_.max_score_points;
    if (cfg_.alpha + cfg_.beta + cfg_.shape_weight <= 0.0) throw Error("alpha + beta + shape_weight must be > 0");
  }

  // Registers each pair (lista::objreg's multi-hypothesis ICP) on all threads.
  std::vector<double> shape_fit(const std::vector<std::pair<const Object*, const Object*>>& pairs, Context& ctx) const {
    std::vector<double> fit(pairs.size(), 0.0);
    std::vector<std::pair<double, double>> shares(pairs.size());
    std::vector<char> upright_decided(pairs.size(), 0);
    ctx.progress().begin("shape check of candidate pairs", pairs.size());
    parallel_for(pairs.size(), ctx.threads(), [&](size_t k) {
      if (ctx.cancelled()) return;
      const auto& a = pairs[k].first->points.xyz;
      const auto& b = pairs[k].second->points.xyz;
      registration::IcpConfig cfg = shape_;
      const Object &oa = *pairs[k].first, &ob = *pairs[k].second;
      // Objects moved on the floor stay upright: the best upright pose is
      // the one judged, not a better-scoring one lying on its side.
      // With the lift gate on, their yaw hypotheses start base on base (a
      // view missing its top has its centroid low).
      if (upright_poses_) {
        cfg.admissible = [&](const Eigen::Isometry3d& t) {
          return registration::stays_on_floor(oa, ob, t, max_lift_, max_tilt_);
        };
        if (max_lift_ > 0.0) cfg.floor_lift = registration::floor_lift(oa, ob);
      }
      registration::IcpResult r = registration::icp_refine(a, b, cfg);
      // Judged again on the surfaces, not the points: a sparse scanner's
      // views interleave their rings (registration::surface_share).
      if (surface_.gap > 0.0) {
        const registration::SurfaceShares on = registration::surface_shares(a, b, r.transform, surface_);
        r.source_inliers = on.source;
        r.target_inliers = on.target;
      }
      fit[k] = registration::shape_fit(r.source_inliers, r.target_inliers);
      shares[k] = {r.source_inliers, r.target_inliers};
      upright_decided[k] = r.inadmissible_preferred;
      // A registration that lifts a floor-standing object (a desk's top onto a
      // cabinet's) or tips it over fits two things, not one object moved.
      // -1: never a candidate, whatever min_shape_fit (the cost clamps it to a misfit of 1).
      if (!registration::stays_on_floor(oa, ob, r.transform, max_lift_, max_tilt_)) fit[k] = -1.0;
      ctx.progress().advance();
    });
    ctx.progress().end();
    ctx.throw_if_cancelled();
    for (size_t k = 0; k < pairs.size(); ++k) {
      char line[200];
      std::snprintf(line, sizeof line, "shape fit of objects %d -> %d: %.3f (shares explained %.3f / %.3f)%s%s",
                    pairs[k].first->id, pairs[k].second->id, fit[k], shares[k].first, shares[k].second,
                    upright_decided[k] ? ", upright pose (a tipped or lifted one scored better)" : "",
                    fit[k] < 0.0 ? ", registered off its floor: no candidate" : "");
      ctx.debug(line);
    }
    return fit;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const auto& objects = in.get<ObjectSet>("objects");
    const auto& descriptors = in.get<DescriptorSet>("descriptors");
    const Groups* groups = in.has("groups") ? &in.get<Groups>("groups") : nullptr;
    std::string warning;
    const PairFit fit = [&](const std::vector<std::pair<const Object*, const Object*>>& pairs) {
      return shape_fit(pairs, ctx);
    };
    Matches m = match_weighted(objects, descriptors, groups, cfg_, &warning, fit);
    if (!warning.empty()) ctx.warn(warning);
    int moved = 0, removed = 0, added = 0;
    for (const auto& c : m.objects) {
      if (c.status == ChangeStatus::moved) ++moved;
      else if (c.status == ChangeStatus::removed) ++removed;
      else ++added;
    }
    ctx.info(std::to_string(moved) + " moved, " + std::to_string(removed) + " removed, " +
             std::to_string(added) + " added");
    ctx.record("moved", moved);
    ctx.record("removed", removed);
    ctx.record("added", added);
    Outputs out;
    out.put("matches", std::move(m));
    return out;
  }

 private:
  WeightedMatchConfig cfg_;
  registration::IcpConfig shape_;
  registration::SurfaceShareConfig surface_;
  double max_lift_ = 0.0, max_tilt_ = 180.0;
  bool upright_poses_ = true;
};

StageInfo info() {
  StageInfo s;
  s.name = "match.weighted";
  s.version = "1.10.0";
  s.summary = "Object correspondences by weighted physical + descriptor + shape-fit cost, optimal assignment";
  s.doc =
      "For each pair of consecutive missions, the cost of pairing object i (earlier) with j (later) is "
      "alpha * norm(centroid distance) + beta * norm(descriptor L2 distance) + shape_weight * (1 - shape fit) "
      "(+ group_penalty across groups when group_mode = soft: the penalty only decides between rival "
      "partners, it does not count against max_cost, so a group never vetoes a pair the gates accept; hard "
      "does). normalization = max divides the physical term by its largest candidate value and the descriptor term by the largest descriptor distance between any "
      "two objects; minmax is the paper's (x - min) / (max - min), which stretches descriptor noise between "
      "identical objects to the full range. Candidates must lie within max_distance metres (0 = any distance), keep their size "
      "(height and footprint-rectangle sides within max(max_size_change x the larger, size_slack)), "
      "max_descriptor_distance (if > 0), then fit as one rigid object: each surviving pair is registered "
      "(lista::objreg multi-hypothesis ICP on shape_voxel-downsampled points, the view covering fewer voxels "
      "moved onto the other; started from yaw turns about the centroids and, with corner_hypotheses, when the "
      "footprints differ in size, corner on corner: a partial view shares a corner with the whole) and shape fit = 0.75 x the larger + 0.25 x the smaller share of points on the other "
      "object's surface: within shape_distance of one of its points, or, between a sparse scanner's rings, "
      "within shape_distance / 2 of the plane its points within shape_gap span around it (a partial view must "
      "be explained; the other view at least in part); fit < min_shape_fit is no candidate, nor is a pair standing on floors in both missions (floor_z "
      "known) that the registration lifts by more than max_lift relative to the floors or tilts by more than "
      "max_tilt (a desk's top fitted onto a cabinet's is two things, not one moved); with upright_poses such a "
      "pair is registered among the poses that keep it on its floor, its yaw turns started floor on floor "
      "(the best of them is judged), without it "
      "the best pose of all is judged and refused when off the floor. Last, cost <= max_cost (< 0: alpha + beta + shape_weight x "
      "(1 - min_shape_fit)). shape_weight = 0 and min_shape_fit = 0 give the paper's two-term cost and skip "
      "the registration. The Hungarian algorithm picks the cheapest set "
      "of pairs, each pair only if cheaper than leaving both unmatched. With change points that say against "
      "which neighbouring mission they changed (PointSet::changed_against, filled by the volumetric stages), "
      "a pair of missions m, m+1 also needs one end changed against the other, and (far_side_explains) neither "
      "end may have changed mostly against its other neighbour (m-1, m+2). Matched objects are 'moved' "
      "(match = partner in the next mission, else the previous one); an unmatched object is 'removed' when "
      "it changed against the next mission (or is in the first), 'added' when only against the previous one "
      "(or is in the last). history chains matches across all missions. Confidence of a move = 0.5 * (1 - "
      "ambiguity) + 0.5 * group confidence, ambiguity = w / (cost of the best rival pair of either end); "
      "of an unmatched object = 0.5 * min(1, cheapest rejected candidate cost / max_cost; 1 if none) + "
      "0.5 * group confidence; either then becomes evidence * (0.5 + 0.5 * it), a move's also times its shape fit (a move's ends each their own; "
      "both ends then carry the lower: one move, one confidence), evidence = 1 - exp(-v / evidence_voxels), v = the object's occupied "
      "evidence_voxel cubes (the surface it shows): a change a few voxels large is mostly a fragment, a "
      "leftover or noise.";
  s.inputs = {{"objects", "objects", "changed objects of all missions"},
              {"descriptors", "descriptors", "one descriptor per object"},
              {"groups", "groups", "descriptor groups (soft or hard constraint)", true}};
  s.outputs = {{"matches", "matches", "status, partner, cost, confidence and history of every object"}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<MatchStageConfig>& param_table() {
  using C = MatchStageConfig;
  static const ParamTable<C> table = [] {
    ParamTable<C> t;
    t.bind("alpha", &C::alpha, "weight of the normalised physical distance").range(0.0, 100.0);
    t.bind("beta", &C::beta, "weight of the normalised descriptor distance").range(0.0, 100.0);
    t.bind("normalization", &C::normalization, "how each distance is scaled to [0,1]").one_of({"max", "minmax"});
    t.bind("group_mode", &C::group_mode, "how descriptor groups constrain pairs").one_of({"soft", "hard", "ignore"});
    t.bind("group_penalty", &C::group_penalty,
           "cost added to a cross-group pair (group_mode = soft); prefers same-group partners, never vetoes")
        .range(0.0, 100.0);
    t.bind("max_size_change", &C::max_size_change,
           "size gate, a cheap pre-filter before the shape check: largest relative change of height or "
           "footprint-rectangle sides of a pair (a rigid object keeps its size, but a partial view shows less of "
           "it); 0 = off")
        .range(0.0, 10.0);
    t.bind("size_slack", &C::size_slack, "size change always allowed (partial views, noise)").range(0.0, 10.0).unit("m");
    t.bind("max_distance", &C::max_distance,
           "farthest centroid displacement accepted as a move; 0 = no limit (a site's scale is not known: the size "
           "and shape gates keep unlike objects apart, the physical term prefers near partners)")
        .range(0.0, 1e6)
        .unit("m");
    t.bind("max_descriptor_distance", &C::max_descriptor_distance, "largest descriptor distance of a pair; 0 = no gate")
        .at_least(0.0);
    t.bind("max_cost", &C::max_cost,
           "largest weighted cost of a pair; < 0 = alpha + beta + shape_weight x (1 - min_shape_fit)")
        .range(-1.0, 1e6);
    t.bind("shape_weight", &C::shape_weight,
           "weight of the shape misfit (1 - fit after registering the pair); 0 = the paper's two terms")
        .range(0.0, 100.0);
    t.bind("min_shape_fit", &C::min_shape_fit,
           "shape gate: smallest fit of a pair (shares of points on the other object's surface after registration; "
           "shape_distance, shape_gap); 0 = off")
        .range(0.0, 1.0);
    t.bind("far_side_explains", &C::far_side_explains,
           "3+ missions: an object that changed mostly against its other neighbour (more than twice as many of its "
           "points changed against it as against this pair's mission) is that change's end and no candidate "
           "between this pair of missions; false = every object a candidate");
    t.bind("shape_voxel", &C::shape_voxel, "voxel size the shape check downsamples to").range(0.005, 1.0).unit("m");
    t.bind("shape_distance", &C::shape_distance, "a registered point within this distance of the other object counts as explained")
        .range(0.001, 1.0)
        .unit("m");
    t.bind("shape_gap", &C::shape_gap,
           "a registered point farther than shape_distance from the other object still counts as explained when "
           "the other object's points within this distance span a surface around it (a sparse scanner's rings) and "
           "it lies within shape_distance / 2 of that surface; 0 = points only")
        .range(0.0, 1.0)
        .unit("m");
    t.bind("evidence_voxel", &C::evidence_voxel, "cube edge for measuring the surface an object shows (confidence)")
        .range(0.01, 1.0)
        .unit("m");
    t.bind("evidence_voxels", &C::evidence_voxels,
           "confidence = evidence x (0.5 + 0.5 x the matching and group terms), x the shape fit for a move; "
           "evidence = 1 - exp(-v / evidence_voxels), v = the object's occupied evidence_voxel cubes (0.63 at this "
           "many); 0 = the matching and group terms alone")
        .range(0.0, 1e6);
    t.bind("max_lift", &C::max_lift,
           "floor gate: a pair standing on floors in both missions (floor_z known) must not be lifted by more than "
           "this, relative to the floors, when registered; 0 = off")
        .range(0.0, 100.0)
        .unit("m");
    t.bind("max_tilt", &C::max_tilt, "floor gate: nor tilted by more than this (180 = off)").range(1.0, 180.0).unit("deg");
    t.bind("upright_poses", &C::upright_poses,
           "floor gate: a pair standing on floors in both missions is registered among upright poses only "
           "(max_lift, max_tilt), so a better-scoring pose lying on its side does not refuse it; false = register "
           "freely, refuse the pair when that pose is off the floor");
    t.bind("corner_hypotheses", &C::corner_hypotheses,
           "shape check: views whose footprints differ in size (a side by more than 0.1 m) that no yaw turn "
           "explains (90 % of the moved view within shape_distance) are also registered from the poses that put a "
           "corner of one footprint on a corner of the other (half a table seen shares a corner with the whole, "
           "not its centre): the 4 of them (of up to 16) that score best as they stand");
    return t;
  }();
  return table;
}

void register_stages(Registrar& r) {
  r.add(info(), [](const Params& p) { return std::make_unique<WeightedMatchStage>(p); });
}

}  // namespace

}  // namespace lista::matching

LISTA_PLUGIN(lista::matching::register_stages)
