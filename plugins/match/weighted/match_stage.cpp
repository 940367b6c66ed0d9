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
      "Pairs the changed objects of consecutive missions by a weighted cost (centroid and descriptor distance, "
      "shape fit after registration, group penalty) under size, floor and shape gates, with an optimal "
      "assignment; sets each object's status, partner and confidence. "
      "Details: docs/matching.md, \"The cost of a pair\".";
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
           "size gate before the shape check: largest relative change of height or footprint-rectangle sides of a pair; 0 = off")
        .range(0.0, 10.0);
    t.bind("size_slack", &C::size_slack, "size change always allowed (partial views, noise)").range(0.0, 10.0).unit("m");
    t.bind("max_distance", &C::max_distance,
           "farthest centroid displacement accepted as a move; 0 = no limit")
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
           "3+ missions: an object that changed mostly against its other neighbour is no candidate between this pair of missions");
    t.bind("shape_voxel", &C::shape_voxel, "voxel size the shape check downsamples to").range(0.005, 1.0).unit("m");
    t.bind("shape_distance", &C::shape_distance, "a registered point within this distance of the other object counts as explained")
        .range(0.001, 1.0)
        .unit("m");
    t.bind("shape_gap", &C::shape_gap,
           "a registered point off the other object still counts within shape_distance / 2 of the surface that the other's points within this distance span; 0 = points only")
        .range(0.0, 1.0)
        .unit("m");
    t.bind("evidence_voxel", &C::evidence_voxel, "cube edge for measuring the surface an object shows (confidence)")
        .range(0.01, 1.0)
        .unit("m");
    t.bind("evidence_voxels", &C::evidence_voxels,
           "confidence scale: evidence = 1 - exp(-v / this), v = the object's occupied evidence_voxel cubes; 0 = no evidence factor")
        .range(0.0, 1e6);
    t.bind("max_lift", &C::max_lift,
           "floor gate: a pair standing on floors in both missions (floor_z known) must not be lifted by more than "
           "this, relative to the floors, when registered; 0 = off")
        .range(0.0, 100.0)
        .unit("m");
    t.bind("max_tilt", &C::max_tilt, "floor gate: nor tilted by more than this (180 = off)").range(1.0, 180.0).unit("deg");
    t.bind("upright_poses", &C::upright_poses,
           "a pair standing on floors in both missions is registered among upright poses only (max_lift, max_tilt); false = refused when its best pose is off the floor");
    t.bind("corner_hypotheses", &C::corner_hypotheses,
           "shape check: views of different footprint sizes that no yaw turn explains are also registered corner on corner");
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
