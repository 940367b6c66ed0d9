// Test helpers for the synthetic scene: how many points of each label a
// change result holds, per mission. Header-only; used by the volumetric
// plugins' tests and the benchmark.
#pragma once

#include <lista/missions.hpp>

#include <cstdint>
#include <map>
#include <set>
#include <utility>

namespace lista::raycast {

// label -> number of points, over one mission's scans.
inline std::map<uint32_t, size_t> label_counts(const Mission& m) {
  std::map<uint32_t, size_t> n;
  for (const Scan& s : m.scans)
    for (uint32_t l : s.points->label) ++n[l];
  return n;
}

inline std::map<uint32_t, size_t> label_counts(const PointSet& p) {
  std::map<uint32_t, size_t> n;
  for (uint32_t l : p.label) ++n[l];
  return n;
}

// (scan, index) pairs of a change set, for comparing two results.
inline std::set<std::pair<uint32_t, uint32_t>> provenance(const PointSet& p) {
  std::set<std::pair<uint32_t, uint32_t>> s;
  for (size_t i = 0; i < p.size(); ++i) s.emplace(p.scan[i], p.index[i]);
  return s;
}

}  // namespace lista::raycast
