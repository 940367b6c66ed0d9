// The data contract's truth (sect. 3) for benchmark programs: which objects
// changed between two missions, and per-point scores of raw change points.
#pragma once

#include <lista/missions.hpp>
#include <lista_io/report.hpp>

#include <set>
#include <string>
#include <utility>
#include <vector>

struct PointScore {
  uint64_t tp = 0, fp = 0, tn = 0, fn = 0;
  double precision() const { return tp + fp ? double(tp) / (tp + fp) : 0.0; }
  double recall() const { return tp + fn ? double(tp) / (tp + fn) : 0.0; }
  double f1() const { const double p = precision(), r = recall(); return p + r > 0 ? 2 * p * r / (p + r) : 0.0; }
  double iou() const { return tp + fp + fn ? double(tp) / (tp + fp + fn) : 0.0; }
};

// Ids of the objects added, removed or moved (> 5 cm or > 5 deg) between
// missions `a` and `b`; dynamic objects are never among them.
std::set<uint32_t> objects_changed_between(const lista::io::GroundTruth& truth, const std::string& a,
                                           const std::string& b);

// Ids of the dynamic objects (people walking): their points are left out of every score.
std::set<uint32_t> dynamic_objects(const lista::io::GroundTruth& truth);

// A point is truly changed when its label names an object changed between
// its mission and a neighbouring one. `changed[m]` holds the (scan, index)
// pairs predicted changed in mission m.
PointScore score_points(const lista::MissionSet& missions, const lista::io::GroundTruth& truth,
                        const std::vector<std::set<std::pair<uint32_t, uint32_t>>>& changed);
