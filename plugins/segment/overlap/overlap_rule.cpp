#include "overlap_rule.hpp"

#include <lista/error.hpp>
#include <lista_geometry/object_geometry.hpp>
#include <lista_geometry/union_find.hpp>

#include <algorithm>
#include <limits>
#include <map>

namespace lista::segment {
namespace {

double inside(const Object& a, const Object& b, double margin) {
  if (a.points.empty()) return 0.0;
  const Eigen::Vector3f lo = b.bbox_min.array() - float(margin), hi = b.bbox_max.array() + float(margin);
  // Most pairs are far apart: disjoint boxes need no point test.
  if ((a.bbox_max.array() < lo.array()).any() || (a.bbox_min.array() > hi.array()).any()) return 0.0;
  size_t n = 0;
  for (const auto& p : a.points.xyz) n += (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  return double(n) / double(a.points.size());
}

using geometry::box_gap;

float point_box_distance(const Eigen::Vector3f& p, const Object& b) {
  return (b.bbox_min - p).cwiseMax(p - b.bbox_max).cwiseMax(0.f).norm();
}

std::vector<uint32_t> adjacent_missions(uint32_t m, size_t missions) {
  std::vector<uint32_t> r;
  if (m > 0) r.push_back(m - 1);
  if (m + 1 < missions) r.push_back(m + 1);
  return r;
}

}  // namespace

ObjectSet merge_split_by_overlap(const ObjectSet& input, const OverlapConfig& c, OverlapStats* stats) {
  if (c.margin < 0 || c.merge_gap < 0) throw Error("margin and merge_gap must be >= 0");
  // Work on a copy with bounds recomputed: the rule must not trust stale boxes.
  ObjectSet in = input;
  for (auto& o : in.objects) o.update_geometry();
  OverlapStats st;
  const size_t n = in.objects.size();
  std::map<uint32_t, std::vector<size_t>> by_mission;
  for (size_t i = 0; i < n; ++i) {
    if (in.objects[i].mission >= std::max<size_t>(in.missions.size(), 1))
      throw Error("object " + std::to_string(in.objects[i].id) + " names mission " +
                  std::to_string(in.objects[i].mission) + " but there are " +
                  std::to_string(in.missions.size()));
    by_mission[in.objects[i].mission].push_back(i);
  }

  // 1. Merges: fragments held together by one object of a neighbouring mission.
  geometry::UnionFind dsu(n);
  for (auto& [m, own] : by_mission)
    for (uint32_t other : adjacent_missions(m, in.missions.size())) {
      auto it = by_mission.find(other);
      if (it == by_mission.end()) continue;
      for (size_t b : it->second) {
        std::vector<size_t> inside_b;
        for (size_t a : own)
          if (inside(in.objects[a], in.objects[b], c.margin) >= c.merge_ratio) inside_b.push_back(a);
        for (size_t x = 0; x < inside_b.size(); ++x)
          for (size_t y = x + 1; y < inside_b.size(); ++y)
            if (box_gap(in.objects[inside_b[x]], in.objects[inside_b[y]]) <= c.merge_gap)
              dsu.unite(inside_b[x], inside_b[y]);
      }
    }
  std::vector<Object> merged;
  std::map<size_t, size_t> slot_of_root;
  for (size_t i = 0; i < n; ++i) {
    const size_t r = dsu.find(i);
    auto [it, added] = slot_of_root.emplace(r, merged.size());
    if (added) {
      merged.push_back(in.objects[i]);
    } else {
      merged[it->second].points.append(in.objects[i].points);
      ++st.merged;
    }
  }
  for (auto& o : merged) o.update_geometry();

  // 2. Splits: a composite that holds several separate objects of a neighbour.
  std::map<uint32_t, std::vector<size_t>> merged_by_mission;
  for (size_t i = 0; i < merged.size(); ++i) merged_by_mission[merged[i].mission].push_back(i);
  ObjectSet out;
  out.missions = in.missions;
  out.dynamics = in.dynamics;
  for (size_t ai = 0; ai < merged.size(); ++ai) {
    const Object& a = merged[ai];
    std::vector<size_t> parts;  // objects of a neighbouring mission inside a
    for (uint32_t other : adjacent_missions(a.mission, in.missions.size()))
      for (size_t b : merged_by_mission[other])
        if (inside(merged[b], a, c.margin) >= c.split_ratio) parts.push_back(b);
    // Keep only parts that are separate from each other.
    std::vector<size_t> separate;
    for (size_t b : parts) {
      bool clash = false;
      for (size_t s : separate)
        clash |= inside(merged[b], merged[s], c.margin) >= c.split_ratio ||
                 inside(merged[s], merged[b], c.margin) >= c.split_ratio ||
                 box_gap(merged[b], merged[s]) <= c.merge_gap;  // near: fragments, not objects
      if (!clash) separate.push_back(b);
    }
    if (separate.size() < 2) {
      out.objects.push_back(a);
      continue;
    }
    std::vector<std::vector<uint32_t>> pick(separate.size());
    for (uint32_t p = 0; p < a.points.size(); ++p) {
      const auto& x = a.points.xyz[p];
      size_t best = 0;
      float best_d = std::numeric_limits<float>::max(), best_c = best_d;
      for (size_t k = 0; k < separate.size(); ++k) {
        const float d = point_box_distance(x, merged[separate[k]]);
        const float dc = (x - merged[separate[k]].centroid).squaredNorm();
        if (d < best_d || (d == best_d && dc < best_c)) best = k, best_d = d, best_c = dc;
      }
      pick[best].push_back(p);
    }
    size_t largest = 0;
    for (size_t k = 1; k < pick.size(); ++k)
      if (pick[k].size() > pick[largest].size()) largest = k;
    for (size_t k = 0; k < pick.size(); ++k)
      if (k != largest && pick[k].size() < c.min_points) {
        pick[largest].insert(pick[largest].end(), pick[k].begin(), pick[k].end());
        pick[k].clear();
      }
    size_t made = 0;
    for (auto& idx : pick) {
      if (idx.empty()) continue;
      std::sort(idx.begin(), idx.end());
      Object part;
      part.mission = a.mission;
      part.points = a.points.select(idx);
      part.update_geometry();
      out.objects.push_back(std::move(part));
      ++made;
    }
    if (made > 1) ++st.split;
  }
  out.renumber();
  if (stats) *stats = st;
  return out;
}

}  // namespace lista::segment
