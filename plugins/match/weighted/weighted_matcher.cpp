#include "weighted_matcher.hpp"

#include "hungarian.hpp"
#include "pair_costs.hpp"

#include <lista/error.hpp>
#include <lista_geometry/union_find.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_set>

namespace lista::match {

namespace {

// What pairing the consecutive missions gave each object (aligned with
// objects.objects).
struct Pairing {
  explicit Pairing(const ObjectSet& objects)
      : next(objects.objects.size(), -1),
        prev(objects.objects.size(), -1),
        next_cost(objects.objects.size(), 0.0),
        prev_cost(objects.objects.size(), 0.0),
        ambiguity(objects.objects.size(), 0.0),
        move_fit(objects.objects.size(), 1.0),
        had_candidate(objects.objects.size(), false),
        best_rejected(objects.objects.size(), std::numeric_limits<double>::max()),
        chains(objects.objects.size()) {
    for (size_t i = 0; i < objects.objects.size(); ++i) index[objects.objects[i].id] = i;
  }
  std::map<int, size_t> index;      // object id -> position in objects.objects
  std::vector<int> next, prev;      // partner ids in the next / previous mission, -1 none
  std::vector<double> next_cost, prev_cost;
  std::vector<double> ambiguity;    // 0 = unambiguous, 1 = a rival as good
  std::vector<double> move_fit;     // shape fit of the object's move(s), the lower; 1 = unchecked
  std::vector<bool> had_candidate;  // some pair through it passed the gates
  std::vector<double> best_rejected;  // the cheapest such pair not chosen
  geometry::UnionFind chains;       // objects one chain of moves links
};

// Checks the configuration and the objects; warns of objects without a
// descriptor. Returns the cost gate.
double checked_gate(const ObjectSet& objects, const DescriptorSet& descriptors, const WeightedMatchConfig& cfg,
                    std::string* warning, const PairFit& fit) {
  if ((cfg.shape_weight > 0.0 || cfg.shape_gate.enabled) && !fit) throw Error("the shape term needs a pair fit function");
  // The automatic gate: the costliest pair that passes every other gate.
  const double max_cost = cfg.cost_gate.automatic ? cfg.alpha + cfg.beta + cfg.shape_weight * (1.0 - cfg.shape_gate.bar())
                                                  : cfg.cost_gate.max_cost;
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

  return max_cost;
}

// The ChangedAgainst sides an object mostly changed against: a side counts
// when at least half as many points changed against it as against the other.
// Without the channel: either.
uint8_t mainly_changed_against(const PointSet& points) {
  if (!points.has_changed_against()) return changed_against_either;
  size_t previous = 0, next = 0;
  for (uint8_t b : points.changed_against) {
    if (b & changed_against_previous) ++previous;
    if (b & changed_against_next) ++next;
  }
  const size_t most = std::max(previous, next);
  uint8_t bits = 0;
  if (most > 0 && 2 * previous >= most) bits |= changed_against_previous;
  if (most > 0 && 2 * next >= most) bits |= changed_against_next;
  return bits;
}

// Pairs the changed objects of missions m and m + 1 (`against`: the
// neighbouring missions each object changed against; `mainly`: those it
// mostly changed against) and records it in `s`.
void pair_missions(size_t m, const ObjectSet& objects, const DescriptorSet& descriptors, const Groups* groups,
                   const WeightedMatchConfig& cfg, const PairFit& fit, double desc_scale, double max_cost,
                   const std::vector<uint8_t>& against, const std::vector<uint8_t>& mainly, Pairing& s) {
  const size_t n_obj = objects.objects.size();
  // A move from m to m+1 leaves change against each other at one end at
  // least (at both, unless m+1 never observed where the object stood in
  // m, or m where it stands in m+1: unknown space is never change). Two
  // objects found only against m-1 and m+2 are no pair: the same scene
  // seen twice with no change between would pair different objects across
  // the gap.
  // With far_side_explains, an object that changed mainly against its other
  // neighbour (m-1 for a, m+2 for b) is that change's end and takes no part:
  // a sofa left alone from A to B and moved in C was paired with a sofa
  // removed from A (docs/matching.md, "Three or more missions").
  std::vector<const Object*> a, b;
  std::vector<bool> a_changed, b_changed;  // against the other mission of the pair
  for (size_t i = 0; i < n_obj; ++i) {
    const Object& o = objects.objects[i];
    const uint8_t main = mainly[i];
    if (o.mission == m) {
      if (cfg.far_side_explains && (main & changed_against_previous) && !(main & changed_against_next)) continue;
      a.push_back(&o), a_changed.push_back(against[i] & changed_against_next);
    }
    if (o.mission == m + 1) {
      if (cfg.far_side_explains && (main & changed_against_next) && !(main & changed_against_previous)) continue;
      b.push_back(&o), b_changed.push_back(against[i] & changed_against_previous);
    }
  }
  if (a.empty() || b.empty()) return;
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
  const double penalty = cfg.groups.mode == GroupMode::soft ? std::max(0.0, cfg.groups.penalty) : 0.0;
  const double leave = (max_cost + penalty) * (1.0 + 1e-9) + 1e-12;
  const std::vector<int> assigned = assign_with_gate(pc.weighted, pc.allowed, leave);

  auto cost_margin = [&](double w, double rival) {
    // How much of the rival's cost the chosen pair saves: 0 = tie.
    return rival <= 0.0 ? (w <= 0.0 ? 1.0 : 0.0) : std::clamp(1.0 - w / rival, 0.0, 1.0);
  };
  for (size_t i = 0; i < a.size(); ++i) {
    const size_t ia = s.index[a[i]->id];
    for (size_t j = 0; j < b.size(); ++j) {
      if (!pc.allowed(i, j)) continue;
      const size_t jb = s.index[b[j]->id];
      s.had_candidate[ia] = s.had_candidate[jb] = true;
      if (assigned[i] != static_cast<int>(j)) {
        s.best_rejected[ia] = std::min(s.best_rejected[ia], pc.weighted(i, j));
        s.best_rejected[jb] = std::min(s.best_rejected[jb], pc.weighted(i, j));
      }
    }
    if (assigned[i] < 0) continue;
    const int j = assigned[i];
    const size_t jb = s.index[b[j]->id];
    const double w = pc.weighted(i, j);
    s.next[ia] = b[j]->id, s.next_cost[ia] = w;
    s.prev[jb] = a[i]->id, s.prev_cost[jb] = w;
    const double pair_fit = 1.0 - pc.shape(i, j);
    s.move_fit[ia] = std::min(s.move_fit[ia], pair_fit);
    s.move_fit[jb] = std::min(s.move_fit[jb], pair_fit);
    s.chains.unite(ia, jb);
    // Rivals: the next best partner of either end.
    double rival = std::numeric_limits<double>::max();
    for (size_t jj = 0; jj < b.size(); ++jj)
      if (static_cast<int>(jj) != j && pc.allowed(i, jj)) rival = std::min(rival, pc.weighted(i, jj));
    for (size_t ii = 0; ii < a.size(); ++ii)
      if (ii != i && pc.allowed(ii, j)) rival = std::min(rival, pc.weighted(ii, j));
    const double margin = rival == std::numeric_limits<double>::max() ? 1.0 : cost_margin(w, rival);
    s.ambiguity[ia] = std::max(s.ambiguity[ia], 1.0 - margin);
    s.ambiguity[jb] = std::max(s.ambiguity[jb], 1.0 - margin);
  }
}


// Each object's status, partner, confidence and chain of moves.
Matches changes_from(const ObjectSet& objects, const Groups* groups, const WeightedMatchConfig& cfg,
                     double max_cost, const std::vector<uint8_t>& against, Pairing& s) {
  const size_t n_missions = objects.missions.size();
  const size_t n_obj = objects.objects.size();
  auto group_conf = [&](int id) {
    if (!groups) return 1.0;
    for (size_t k = 0; k < groups->object_ids.size(); ++k)
      if (groups->object_ids[k] == id && k < groups->confidence.size()) return groups->confidence[k];
    return 0.0;
  };
  std::map<size_t, std::vector<size_t>> chain_members;
  for (size_t i = 0; i < n_obj; ++i) chain_members[s.chains.find(i)].push_back(i);

  Matches out;
  out.method = "match.weighted";
  out.objects.resize(n_obj);
  for (size_t i = 0; i < n_obj; ++i) {
    const Object& o = objects.objects[i];
    ObjectChange& c = out.objects[i];
    c.object_id = o.id;
    const double g = group_conf(o.id);
    if (s.next[i] >= 0 || s.prev[i] >= 0) {
      c.status = ChangeStatus::moved;
      // The partner in the next mission if any, else in the previous one.
      c.match = s.next[i] >= 0 ? s.next[i] : s.prev[i];
      c.cost = s.next[i] >= 0 ? s.next_cost[i] : s.prev_cost[i];
      c.confidence = 0.5 * (1.0 - s.ambiguity[i]) + 0.5 * g;
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
      const double alone = s.had_candidate[i] ? std::clamp(s.best_rejected[i] / max_cost, 0.0, 1.0) : 1.0;
      c.confidence = 0.5 * alone + 0.5 * g;
    }
    // A change is as sure as the surface it shows (a few voxels are mostly
    // a fragment, a leftover or noise), a move also as its shape fit. The
    // terms above count for half.
    if (cfg.evidence.enabled) {
      c.confidence = surface_evidence(o, cfg) * (0.5 + 0.5 * c.confidence);
      if (c.status == ChangeStatus::moved) c.confidence *= s.move_fit[i];
    }
    c.confidence = std::clamp(c.confidence, 0.0, 1.0);
    std::vector<size_t> members = chain_members[s.chains.find(i)];
    std::sort(members.begin(), members.end(), [&](size_t x, size_t y) {
      return objects.objects[x].mission != objects.objects[y].mission
                 ? objects.objects[x].mission < objects.objects[y].mission
                 : objects.objects[x].id < objects.objects[y].id;
    });
    for (size_t k : members) c.history.push_back(objects.objects[k].id);
  }
  return out;
}

// A move is as sure as its less sure end: both reports of one move say the
// same (with two missions exactly; a middle object takes the lower of its
// two moves). Per end they differed by the ends' own group confidence.
void one_confidence_per_move(Matches& out, const ObjectSet& objects, const Pairing& s) {
  const size_t n_obj = objects.objects.size();
  std::vector<double> own(n_obj);
  for (size_t i = 0; i < n_obj; ++i) own[i] = out.objects[i].confidence;
  for (size_t i = 0; i < n_obj; ++i)
    for (int partner : {s.next[i], s.prev[i]})
      if (partner >= 0)
        out.objects[i].confidence = std::min(out.objects[i].confidence, own[s.index.at(partner)]);
}

}  // namespace

double surface_evidence(const Object& object, const WeightedMatchConfig& cfg) {
  if (!cfg.evidence.enabled) return 1.0;
  const double inv = 1.0 / cfg.evidence.voxel;
  std::unordered_set<uint64_t> cubes;
  cubes.reserve(object.points.size());
  for (const auto& p : object.points.xyz)
    cubes.insert(geometry::voxel_key((p.cast<double>() * inv).array().floor().cast<int>()));
  return 1.0 - std::exp(-double(cubes.size()) / cfg.evidence.voxels);
}

Matches match_weighted(const ObjectSet& objects, const DescriptorSet& descriptors,
                       const Groups* groups, const WeightedMatchConfig& cfg, std::string* warning,
                       const PairFit& fit) {
  const double max_cost = checked_gate(objects, descriptors, cfg, warning, fit);
  const size_t n_obj = objects.objects.size();
  const double desc_scale = cfg.normalization == Normalization::max ? descriptor_scale(objects, descriptors) : 0.0;
  // Against which neighbouring missions each object changed (both when the
  // changes carry no such channel).
  std::vector<uint8_t> against(n_obj);
  for (size_t i = 0; i < n_obj; ++i) against[i] = objects.objects[i].points.changed_against_all();
  // The neighbours each object mostly changed against (a few points at the
  // fringe of a still object do not count).
  std::vector<uint8_t> mainly(n_obj, changed_against_either);
  if (cfg.far_side_explains)
    for (size_t i = 0; i < n_obj; ++i) mainly[i] = mainly_changed_against(objects.objects[i].points);
  Pairing s(objects);
  for (size_t m = 0; m + 1 < objects.missions.size(); ++m)
    pair_missions(m, objects, descriptors, groups, cfg, fit, desc_scale, max_cost, against, mainly, s);
  Matches out = changes_from(objects, groups, cfg, max_cost, against, s);
  one_confidence_per_move(out, objects, s);
  return out;
}

}  // namespace lista::match
