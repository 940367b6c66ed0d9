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

namespace lista::match {

namespace {

// The matcher's settings and the stage's own: the shape check's registration
// and floor gate.
struct MatchStageConfig : WeightedMatchConfig {
  struct Shape {
    double voxel = 0.04, distance = 0.05;  // m
    bool surfaces = true;
    double gap = 0.15;  // m
    bool corner_hypotheses = true;
  } shape;
  struct FloorGate {
    bool check_lift = true;
    double max_lift = 0.15;  // m
    bool check_tilt = true;
    double max_tilt = 20.0;  // deg
    bool upright_poses = true;
  } floor_gate;
};

const ParamTable<MatchStageConfig>& param_table();

class WeightedMatchStage : public Stage {
 public:
  explicit WeightedMatchStage(const Params& p) {
    const MatchStageConfig c = param_table().read(p);
    cfg_ = c;
    // stays_on_floor's "no check": no lift (0), any tilt.
    max_lift_ = c.floor_gate.check_lift ? c.floor_gate.max_lift : 0.0;
    max_tilt_ = c.floor_gate.check_tilt ? c.floor_gate.max_tilt : 180.0;
    upright_poses_ = c.floor_gate.upright_poses;
    shape_ = objreg::shape_check_config(c.shape.voxel, c.shape.distance);
    shape_.corner_hypotheses = c.shape.corner_hypotheses;
    surfaces_ = c.shape.surfaces;
    surface_.voxel = shape_.voxel;
    surface_.inlier = shape_.inlier_distance;
    surface_.gap = c.shape.gap;
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
      objreg::IcpConfig cfg = shape_;
      const Object &oa = *pairs[k].first, &ob = *pairs[k].second;
      // Objects moved on the floor stay upright: the best upright pose is
      // the one judged, not a better-scoring one lying on its side.
      // With the lift gate on, their yaw hypotheses start base on base (a
      // view missing its top has its centroid low).
      if (upright_poses_) {
        cfg.admissible = [&](const Eigen::Isometry3d& t) {
          return objreg::stays_on_floor(oa, ob, t, max_lift_, max_tilt_);
        };
        if (max_lift_ > 0.0) cfg.floor_lift = objreg::floor_lift(oa, ob);
      }
      objreg::IcpResult r = objreg::icp_refine(a, b, cfg);
      // Judged again on the surfaces, not the points: a sparse scanner's
      // views interleave their rings (objreg::surface_share).
      if (surfaces_) {
        const objreg::SurfaceShares on = objreg::surface_shares(a, b, r.transform, surface_);
        r.source_inliers = on.source;
        r.target_inliers = on.target;
      }
      fit[k] = objreg::shape_fit(r.source_inliers, r.target_inliers);
      shares[k] = {r.source_inliers, r.target_inliers};
      upright_decided[k] = r.inadmissible_preferred;
      // A registration that lifts a floor-standing object (a desk's top onto a
      // cabinet's) or tips it over fits two things, not one object moved.
      // -1: never a candidate, whatever the shape gate (the cost clamps it to a misfit of 1).
      if (!objreg::stays_on_floor(oa, ob, r.transform, max_lift_, max_tilt_)) fit[k] = -1.0;
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
    return Outputs::of("matches", std::move(m));
  }

 private:
  WeightedMatchConfig cfg_;
  objreg::IcpConfig shape_;
  objreg::SurfaceShareConfig surface_;
  double max_lift_ = 0.0, max_tilt_ = 180.0;
  bool upright_poses_ = true, surfaces_ = true;
};

StageInfo info() {
  StageInfo s;
  s.name = "match.weighted";
  s.version = "1.11.0";
  s.summary = "Object correspondences by weighted physical + descriptor + shape-fit cost, optimal assignment";
  s.doc =
      "Pairs the changed objects of consecutive missions by a weighted cost (centroid and descriptor distance, "
      "shape fit after registration, group penalty) under size, floor and shape gates, with an optimal "
      "assignment; sets each object's status, partner and confidence. "
      "Details: docs/matching.md, \"The cost of a pair\".";
  s.inputs = {{"objects", "objects", "changed objects of all missions"},
              {"descriptors", "descriptors", "one descriptor per object"},
              {"groups", "groups", "descriptor groups (soft or hard constraint)", true}};
  s.outputs = {{"matches", "matches", "status, partner, cost, confidence and history of every object"}};
  s.params = param_table().specs();
  s.renamed = param_table().renames();
  return s;
}

// The flat names before the groups, accepted until the next release; an
// old "0 = off" (max_tilt: 180) reads as the group's switch.
void renamed_flat_names(ParamTable<MatchStageConfig>& t) {
  const std::pair<const char*, const char*> names[] = {
      {"group_mode", "groups.mode"}, {"group_penalty", "groups.penalty"}, {"size_slack", "size_gate.slack"},
      {"shape_voxel", "shape.voxel"}, {"shape_distance", "shape.distance"},
      {"corner_hypotheses", "shape.corner_hypotheses"}, {"evidence_voxel", "evidence.voxel"},
      {"upright_poses", "floor_gate.upright_poses"}};
  for (const auto& [old_name, new_name] : names) t.renamed(old_name, new_name);
  t.renamed("max_distance", "distance_gate.max_distance", "distance_gate.enabled", 0.0);
  t.renamed("max_size_change", "size_gate.max_change", "size_gate.enabled", 0.0);
  t.renamed("max_descriptor_distance", "descriptor_gate.max_distance", "descriptor_gate.enabled", 0.0);
  t.renamed("min_shape_fit", "shape_gate.min_fit", "shape_gate.enabled", 0.0);
  t.renamed("shape_gap", "shape.gap", "shape.surfaces", 0.0);
  t.renamed("evidence_voxels", "evidence.voxels", "evidence.enabled", 0.0);
  t.renamed("max_lift", "floor_gate.max_lift", "floor_gate.check_lift", 0.0);
  t.renamed("max_tilt", "floor_gate.max_tilt", "floor_gate.check_tilt", 180.0);
  t.renamed("max_cost", "cost_gate.max_cost", [](double v) {
    return v < 0.0 ? ParamAssignments{{"cost_gate.automatic", true}}
                   : ParamAssignments{{"cost_gate.automatic", false}, {"cost_gate.max_cost", v}};
  });
}

const ParamTable<MatchStageConfig>& param_table() {
  using C = MatchStageConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("alpha", &C::alpha, "weight of the normalised physical distance").range(0.0, 100.0);
    t.bind("beta", &C::beta, "weight of the normalised descriptor distance").range(0.0, 100.0);
    t.bind("shape_weight", &C::shape_weight,
           "weight of the shape misfit (1 - fit after registering the pair); 0: the paper's two terms").range(0.0, 100.0);
    t.choice("normalization", &C::normalization, {{"max", Normalization::max}, {"minmax", Normalization::minmax}},
             "how each distance is scaled to [0,1]");
    using G = C::GroupConstraint;
    auto groups = t.group("groups", &C::groups);
    groups.choice("mode", &G::mode, {{"soft", GroupMode::soft}, {"hard", GroupMode::hard}, {"ignore", GroupMode::ignore}},
                  "how descriptor groups constrain pairs");
    groups.bind("penalty", &G::penalty, "cost added to a cross-group pair (mode soft); prefers same-group partners, never vetoes")
        .range(0.0, 100.0);
    using D = C::DistanceGate;
    auto distance_gate = t.group("distance_gate", &C::distance_gate);
    distance_gate.bind("enabled", &D::enabled, "refuse pairs whose centroids moved farther than max_distance");
    distance_gate.bind("max_distance", &D::max_distance, "farthest centroid displacement accepted as a move").range(0.0, 1e6).unit("m");
    using Z = C::SizeGate;
    auto size_gate = t.group("size_gate", &C::size_gate);
    size_gate.bind("enabled", &Z::enabled, "refuse pairs of different sizes before the shape check");
    size_gate.bind("max_change", &Z::max_change, "largest relative change of height or footprint-rectangle sides of a pair")
        .range(0.0, 10.0);
    size_gate.bind("slack", &Z::slack, "size change always allowed (partial views, noise)").range(0.0, 10.0).unit("m");
    using R = C::DescriptorGate;
    auto descriptor_gate = t.group("descriptor_gate", &C::descriptor_gate);
    descriptor_gate.bind("enabled", &R::enabled, "refuse pairs whose descriptors differ more than max_distance");
    descriptor_gate.bind("max_distance", &R::max_distance, "largest descriptor distance of a pair (the descriptor's units)")
        .at_least(0.0);
    using K = C::CostGate;
    auto cost_gate = t.group("cost_gate", &C::cost_gate);
    cost_gate.bind("automatic", &K::automatic,
                   "the largest weighted cost of a pair is alpha + beta + shape_weight x (1 - shape_gate.min_fit); false: max_cost");
    cost_gate.bind("max_cost", &K::max_cost, "largest weighted cost of a pair").range(0.0, 1e6);
    using F = C::ShapeGate;
    auto shape_gate = t.group("shape_gate", &C::shape_gate);
    shape_gate.bind("enabled", &F::enabled, "refuse pairs that one rigid object does not explain");
    shape_gate.bind("min_fit", &F::min_fit,
                    "smallest fit of a pair (shares of points on the other object's surface after registration)").range(0.0, 1.0);
    using S = C::Shape;
    auto shape = t.group("shape", &C::shape);
    shape.bind("voxel", &S::voxel, "voxel size the shape check downsamples to").range(0.005, 1.0).unit("m");
    shape.bind("distance", &S::distance, "a registered point within this distance of the other object counts as explained")
        .range(0.001, 1.0).unit("m");
    shape.bind("surfaces", &S::surfaces,
               "a registered point also counts near the surface the other's points span (gap); false: points only");
    shape.bind("gap", &S::gap,
               "a registered point off the other object still counts within distance / 2 of the surface that the "
               "other's points within this distance span").range(0.001, 1.0).unit("m");
    shape.bind("corner_hypotheses", &S::corner_hypotheses,
               "views of different footprint sizes that no yaw turn explains are also registered corner on corner");
    t.bind("far_side_explains", &C::far_side_explains,
           "3+ missions: an object that changed mostly against its other neighbour is no candidate between this pair of missions");
    using E = C::Evidence;
    auto evidence = t.group("evidence", &C::evidence);
    evidence.bind("enabled", &E::enabled, "confidence scaled by the surface an object shows");
    evidence.bind("voxel", &E::voxel, "cube edge for measuring the surface an object shows").range(0.01, 1.0).unit("m");
    evidence.bind("voxels", &E::voxels, "confidence scale: evidence = 1 - exp(-v / this), v = the object's occupied voxel cubes")
        .range(0.01, 1e6);
    using L = C::FloorGate;
    auto floor_gate = t.group("floor_gate", &C::floor_gate);
    floor_gate.bind("check_lift", &L::check_lift,
                    "a pair standing on floors in both missions (floor_z known) is refused when registered lifted, "
                    "relative to the floors, by more than max_lift");
    floor_gate.bind("max_lift", &L::max_lift, "the most lift such a pair is registered with").range(0.001, 100.0).unit("m");
    floor_gate.bind("check_tilt", &L::check_tilt, "or tilted by more than max_tilt");
    floor_gate.bind("max_tilt", &L::max_tilt, "the most tilt such a pair is registered with").range(1.0, 180.0).unit("deg");
    floor_gate.bind("upright_poses", &L::upright_poses,
                    "a pair standing on floors in both missions is registered among upright poses only; false: refused "
                    "when its best pose is off the floor");
    renamed_flat_names(t);
  });
}

}  // namespace

}  // namespace lista::match

LISTA_STAGE_PLUGIN(lista::match::info, lista::match::WeightedMatchStage)
