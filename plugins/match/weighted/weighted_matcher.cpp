#include "weighted_matcher.hpp"

#include "hungarian.hpp"

#include <lista/error.hpp>
#include <lista_geometry/object_geometry.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <unordered_set>

namespace lista::matching {

namespace {

using BoolMatrix = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

struct PairCosts {
  Eigen::MatrixXd physical, descriptor, shape, weighted;
  Eigen::MatrixXd cross;  // the group penalty part of `weighted`
  BoolMatrix allowed;
};

// Scales the entries of `d` where `mask` holds, as configured: "minmax" over
// the masked entries; "max" divides by max(largest masked entry, floor).
void normalise(Eigen::MatrixXd& d, const BoolMatrix& mask, const std::string& how, double floor = 0.0) {
  double lo = std::numeric_limits<double>::max(), hi = 0.0;
  for (int i = 0; i < d.rows(); ++i)
    for (int j = 0; j < d.cols(); ++j)
      if (mask(i, j)) lo = std::min(lo, d(i, j)), hi = std::max(hi, d(i, j));
  if (how == "max") lo = 0.0, hi = std::max(hi, floor);
  const double range = hi - lo;
  for (int i = 0; i < d.rows(); ++i)
    for (int j = 0; j < d.cols(); ++j)
      d(i, j) = range > 1e-12 ? std::clamp((d(i, j) - lo) / range, 0.0, 1.0) : 0.0;
}

// Height and footprint-rectangle sides (larger first): what
// a rigid object keeps when it moves, whatever its yaw.
Eigen::Vector3d size_of(const Object& o) {
  const Eigen::Vector2f e = geometry::horizontal_extents(o.points.xyz);
  return {double(o.bbox_max.z() - o.bbox_min.z()), double(e[0]), double(e[1])};
}

bool same_size(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double relative, double slack) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(a[k] - b[k]) > std::max(slack, relative * std::max(a[k], b[k]))) return false;
  return true;
}

// The largest descriptor distance between any two objects of the scene: the
// descriptor scale for "max" normalisation, so that noise between
// near-identical objects stays small next to real class differences.
double descriptor_scale(const ObjectSet& objects, const DescriptorSet& desc) {
  std::vector<int> rows;
  for (const Object& o : objects.objects)
    if (desc.row_of(o.id) >= 0) rows.push_back(desc.row_of(o.id));
  double best = 0.0;
  for (size_t i = 0; i < rows.size(); ++i)
    for (size_t j = i + 1; j < rows.size(); ++j)
      best = std::max(best, static_cast<double>((desc.values.row(rows[i]) - desc.values.row(rows[j])).norm()));
  return best;
}

PairCosts pair_costs(const std::vector<const Object*>& a, const std::vector<const Object*>& b,
                     const DescriptorSet& desc, const Groups* groups, const WeightedMatchConfig& cfg,
                     double desc_scale, const PairFit& fit, const std::vector<bool>& a_changed,
                     const std::vector<bool>& b_changed) {
  const int n = static_cast<int>(a.size()), m = static_cast<int>(b.size());
  PairCosts pc;
  pc.physical.resize(n, m);
  pc.descriptor.resize(n, m);
  pc.allowed.setConstant(n, m, true);
  pc.cross = Eigen::MatrixXd::Zero(n, m);
  std::vector<Eigen::Vector3d> size_a, size_b;
  if (cfg.max_size_change > 0.0) {
    for (const Object* o : a) size_a.push_back(size_of(*o));
    for (const Object* o : b) size_b.push_back(size_of(*o));
  }
  for (int i = 0; i < n; ++i) {
    const int ra = desc.row_of(a[i]->id);
    for (int j = 0; j < m; ++j) {
      const int rb = desc.row_of(b[j]->id);
      pc.physical(i, j) = (a[i]->centroid - b[j]->centroid).cast<double>().norm();
      // An object without a descriptor is as unlike everything as possible.
      pc.descriptor(i, j) = (ra >= 0 && rb >= 0)
          ? (desc.values.row(ra) - desc.values.row(rb)).cast<double>().norm()
          : std::numeric_limits<double>::quiet_NaN();
      bool ok = (cfg.max_distance <= 0.0 || pc.physical(i, j) <= cfg.max_distance) &&
                (a_changed[size_t(i)] || b_changed[size_t(j)]);
      if (cfg.max_size_change > 0.0 && !same_size(size_a[size_t(i)], size_b[size_t(j)], cfg.max_size_change, cfg.size_slack))
        ok = false;
      if (cfg.max_descriptor_distance > 0.0 && !(pc.descriptor(i, j) <= cfg.max_descriptor_distance))
        ok = false;
      if (groups && cfg.group_mode != "ignore") {
        const int ga = groups->group_of(a[i]->id), gb = groups->group_of(b[j]->id);
        const bool same = ga >= 0 && ga == gb;
        if (!same && cfg.group_mode == "hard") ok = false;
        if (!same) pc.cross(i, j) = cfg.group_penalty;
      }
      pc.allowed(i, j) = ok;
    }
  }
  double dmax = 0.0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (std::isfinite(pc.descriptor(i, j))) dmax = std::max(dmax, pc.descriptor(i, j));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (!std::isfinite(pc.descriptor(i, j))) pc.descriptor(i, j) = dmax;
  // Shape check last: it registers every surviving pair, the costly part.
  pc.shape = Eigen::MatrixXd::Zero(n, m);
  if (cfg.shape_weight > 0.0 || cfg.min_shape_fit > 0.0) {
    std::vector<std::pair<const Object*, const Object*>> todo;
    std::vector<std::pair<int, int>> where;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < m; ++j)
        if (pc.allowed(i, j)) todo.emplace_back(a[size_t(i)], b[size_t(j)]), where.emplace_back(i, j);
    const std::vector<double> f = todo.empty() ? std::vector<double>{} : fit(todo);
    if (f.size() != todo.size()) throw Error("shape fit returned " + std::to_string(f.size()) + " values for " +
                                             std::to_string(todo.size()) + " pairs");
    for (size_t k = 0; k < todo.size(); ++k) {
      const auto [i, j] = where[k];
      pc.shape(i, j) = 1.0 - std::clamp(f[k], 0.0, 1.0);
      if (f[k] < cfg.min_shape_fit) pc.allowed(i, j) = false;
    }
  }
  Eigen::MatrixXd p = pc.physical, d = pc.descriptor;
  normalise(p, pc.allowed, cfg.normalization);
  normalise(d, pc.allowed, cfg.normalization, desc_scale);
  pc.weighted = cfg.alpha * p + cfg.beta * d + cfg.shape_weight * pc.shape + pc.cross;
  return pc;
}

struct UnionFind {
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  size_t root(size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(size_t a, size_t b) { parent[root(b)] = root(a); }
  std::vector<size_t> parent;
};

}  // namespace

double surface_evidence(const Object& object, const WeightedMatchConfig& cfg) {
  if (cfg.evidence_voxels <= 0.0) return 1.0;
  const double inv = 1.0 / cfg.evidence_voxel;
  std::unordered_set<uint64_t> cubes;
  cubes.reserve(object.points.size());
  for (const auto& p : object.points.xyz)
    cubes.insert(geometry::voxel_key((p.cast<double>() * inv).array().floor().cast<int>()));
  return 1.0 - std::exp(-double(cubes.size()) / cfg.evidence_voxels);
}

Matches match_weighted(const ObjectSet& objects, const DescriptorSet& descriptors,
                       const Groups* groups, const WeightedMatchConfig& cfg, std::string* warning,
                       const PairFit& fit) {
  if (cfg.normalization != "max" && cfg.normalization != "minmax")
    throw Error("normalization must be 'max' or 'minmax', got '" + cfg.normalization + "'");
  if (cfg.group_mode != "soft" && cfg.group_mode != "hard" && cfg.group_mode != "ignore")
    throw Error("group_mode must be 'soft', 'hard' or 'ignore', got '" + cfg.group_mode + "'");
  if ((cfg.shape_weight > 0.0 || cfg.min_shape_fit > 0.0) && !fit)
    throw Error("the shape term needs a pair fit function");
  // Default gate: the costliest pair that passes every other gate.
  const double max_cost =
      cfg.max_cost < 0.0 ? cfg.alpha + cfg.beta + cfg.shape_weight * (1.0 - cfg.min_shape_fit) : cfg.max_cost;
  const size_t n_missions = objects.missions.size();
  for (const Object& o : objects.objects)
    if (o.mission >= n_missions)
      throw Error("object " + std::to_string(o.id) + " names mission " + std::to_string(o.mission) +
                  " of " + std::to_string(n_missions));
  size_t missing = 0;
  for (const Object& o : objects.objects)
    if (descriptors.row_of(o.id) < 0) ++missing;
  if (missing && warning)
    *warning = std::to_string(missing) + " objects have no descriptor; treated as unlike all others";

  std::map<int, size_t> index;  // object id -> position in objects.objects
  for (size_t i = 0; i < objects.objects.size(); ++i) index[objects.objects[i].id] = i;
  const size_t n_obj = objects.objects.size();
  std::vector<int> next(n_obj, -1), prev(n_obj, -1);
  std::vector<double> next_cost(n_obj, 0.0), prev_cost(n_obj, 0.0);
  std::vector<double> ambiguity(n_obj, 0.0);  // 0 = unambiguous, 1 = a rival as good
  std::vector<double> move_fit(n_obj, 1.0);   // shape fit of the object's move(s), the lower; 1 = unchecked
  std::vector<bool> had_candidate(n_obj, false);
  std::vector<double> best_rejected(n_obj, std::numeric_limits<double>::max());
  UnionFind chains(n_obj);
  const double desc_scale = cfg.normalization == "max" ? descriptor_scale(objects, descriptors) : 0.0;

  // Against which neighbouring missions each object changed (both when the
  // changes carry no such channel).
  std::vector<uint8_t> against(n_obj);
  for (size_t i = 0; i < n_obj; ++i) against[i] = objects.objects[i].points.changed_against_all();

  for (size_t m = 0; m + 1 < n_missions; ++m) {
    // A move from m to m+1 leaves change against each other at one end at
    // least (at both, unless m+1 never observed where the object stood in
    // m, or m where it stands in m+1: unknown space is never change). Two
    // objects found only against m-1 and m+2 are no pair: the same scene
    // seen twice with no change between would pair different objects across
    // the gap.
    std::vector<const Object*> a, b;
    std::vector<bool> a_changed, b_changed;  // against the other mission of the pair
    for (size_t i = 0; i < n_obj; ++i) {
      const Object& o = objects.objects[i];
      if (o.mission == m) a.push_back(&o), a_changed.push_back(against[i] & changed_against_next);
      if (o.mission == m + 1) b.push_back(&o), b_changed.push_back(against[i] & changed_against_previous);
    }
    if (a.empty() || b.empty()) continue;
    PairCosts pc = pair_costs(a, b, descriptors, groups, cfg, desc_scale, fit, a_changed, b_changed);
    // The gate judges a pair without its group penalty: in soft mode a group
    // only decides between rival partners and never vetoes a pair the gates
    // accept (k-means may split one object's full and partial views).
    for (int i = 0; i < pc.allowed.rows(); ++i)
      for (int j = 0; j < pc.allowed.cols(); ++j)
        if (pc.weighted(i, j) - pc.cross(i, j) > max_cost) pc.allowed(i, j) = false;
    // A pair is used only if it costs less than leaving both alone; leaving
    // costs just above the gate plus the penalty, so that an accepted pair,
    // even across groups and exactly at the gate, still counts.
    const double penalty = cfg.group_mode == "soft" ? std::max(0.0, cfg.group_penalty) : 0.0;
    const double leave = (max_cost + penalty) * (1.0 + 1e-9) + 1e-12;
    const std::vector<int> assigned = assign_with_gate(pc.weighted, pc.allowed, leave);
    std::vector<int> col_owner(b.size(), -1);
    for (size_t i = 0; i < a.size(); ++i)
      if (assigned[i] >= 0) col_owner[assigned[i]] = static_cast<int>(i);

    auto cost_margin = [&](double w, double rival) {
      // How much of the rival's cost the chosen pair saves: 0 = tie.
      return rival <= 0.0 ? (w <= 0.0 ? 1.0 : 0.0) : std::clamp(1.0 - w / rival, 0.0, 1.0);
    };
    for (size_t i = 0; i < a.size(); ++i) {
      const size_t ia = index[a[i]->id];
      for (size_t j = 0; j < b.size(); ++j) {
        if (!pc.allowed(i, j)) continue;
        const size_t jb = index[b[j]->id];
        had_candidate[ia] = had_candidate[jb] = true;
        if (assigned[i] != static_cast<int>(j)) {
          best_rejected[ia] = std::min(best_rejected[ia], pc.weighted(i, j));
          best_rejected[jb] = std::min(best_rejected[jb], pc.weighted(i, j));
        }
      }
      if (assigned[i] < 0) continue;
      const int j = assigned[i];
      const size_t jb = index[b[j]->id];
      const double w = pc.weighted(i, j);
      next[ia] = b[j]->id, next_cost[ia] = w;
      prev[jb] = a[i]->id, prev_cost[jb] = w;
      const double pair_fit = 1.0 - pc.shape(i, j);
      move_fit[ia] = std::min(move_fit[ia], pair_fit);
      move_fit[jb] = std::min(move_fit[jb], pair_fit);
      chains.join(ia, jb);
      // Rivals: the next best partner of either end.
      double rival = std::numeric_limits<double>::max();
      for (size_t jj = 0; jj < b.size(); ++jj)
        if (static_cast<int>(jj) != j && pc.allowed(i, jj)) rival = std::min(rival, pc.weighted(i, jj));
      for (size_t ii = 0; ii < a.size(); ++ii)
        if (ii != i && pc.allowed(ii, j)) rival = std::min(rival, pc.weighted(ii, j));
      const double margin = rival == std::numeric_limits<double>::max() ? 1.0 : cost_margin(w, rival);
      ambiguity[ia] = std::max(ambiguity[ia], 1.0 - margin);
      ambiguity[jb] = std::max(ambiguity[jb], 1.0 - margin);
    }
  }

  auto group_conf = [&](int id) {
    if (!groups) return 1.0;
    for (size_t k = 0; k < groups->object_ids.size(); ++k)
      if (groups->object_ids[k] == id && k < groups->confidence.size()) return groups->confidence[k];
    return 0.0;
  };
  std::map<size_t, std::vector<size_t>> chain_members;
  for (size_t i = 0; i < n_obj; ++i) chain_members[chains.root(i)].push_back(i);

  Matches out;
  out.method = "match.weighted";
  out.objects.resize(n_obj);
  for (size_t i = 0; i < n_obj; ++i) {
    const Object& o = objects.objects[i];
    ObjectChange& c = out.objects[i];
    c.object_id = o.id;
    const double g = group_conf(o.id);
    if (next[i] >= 0 || prev[i] >= 0) {
      c.status = ChangeStatus::moved;
      // The partner in the next mission if any, else in the previous one.
      c.match = next[i] >= 0 ? next[i] : prev[i];
      c.cost = next[i] >= 0 ? next_cost[i] : prev_cost[i];
      c.confidence = 0.5 * (1.0 - ambiguity[i]) + 0.5 * g;
    } else {
      // Changed against the next mission: gone by then, removed; else
      // changed against the previous one only: it appeared, added. Without
      // the channel (either), a middle-mission object counts as removed.
      const bool gone_later = o.mission + 1 < n_missions && (against[i] & changed_against_next);
      const bool new_here = o.mission > 0 && (against[i] & changed_against_previous);
      c.status = gone_later || !new_here ? ChangeStatus::removed : ChangeStatus::added;
      if (n_missions == 1 || o.mission + 1 == n_missions) c.status = ChangeStatus::added;
      // Unmatched: sure when no candidate came near, less so when one was
      // rejected only narrowly.
      const double alone = had_candidate[i] ? std::clamp(best_rejected[i] / max_cost, 0.0, 1.0) : 1.0;
      c.confidence = 0.5 * alone + 0.5 * g;
    }
    // A change is as sure as the surface it shows (a few voxels are mostly
    // a fragment, a leftover or noise), a move also as its shape fit. The
    // terms above count for half.
    if (cfg.evidence_voxels > 0.0) {
      c.confidence = surface_evidence(o, cfg) * (0.5 + 0.5 * c.confidence);
      if (c.status == ChangeStatus::moved) c.confidence *= move_fit[i];
    }
    c.confidence = std::clamp(c.confidence, 0.0, 1.0);
    std::vector<size_t> members = chain_members[chains.root(i)];
    std::sort(members.begin(), members.end(), [&](size_t x, size_t y) {
      return objects.objects[x].mission != objects.objects[y].mission
                 ? objects.objects[x].mission < objects.objects[y].mission
                 : objects.objects[x].id < objects.objects[y].id;
    });
    for (size_t k : members) c.history.push_back(objects.objects[k].id);
  }
  // A move is as sure as its less sure end: both reports of one move say the
  // same (with two missions exactly; a middle object takes the lower of its
  // two moves). Per end they differed by the ends' own group confidence.
  std::map<int, size_t> index_of;
  for (size_t i = 0; i < n_obj; ++i) index_of[objects.objects[i].id] = i;
  std::vector<double> own(n_obj);
  for (size_t i = 0; i < n_obj; ++i) own[i] = out.objects[i].confidence;
  for (size_t i = 0; i < n_obj; ++i)
    for (int partner : {next[i], prev[i]})
      if (partner >= 0)
        out.objects[i].confidence = std::min(out.objects[i].confidence, own[index_of.at(partner)]);
  return out;
}

}  // namespace lista::matching
