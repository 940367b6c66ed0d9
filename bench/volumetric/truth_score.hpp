// Per-point scoring of raw change points against ground_truth.json (data
// contract, sect. 3): a point is truly changed when its label names an object
// added, removed or moved (> 5 cm or > 5 deg) between its mission and a
// neighbouring one; dynamic objects' points are left out.
#pragma once

#include <lista/missions.hpp>
#include <lista_io/report.hpp>

#include <set>
#include <utility>
#include <vector>

struct PointScore {
  uint64_t tp = 0, fp = 0, tn = 0, fn = 0;
  double precision() const { return tp + fp ? double(tp) / (tp + fp) : 0.0; }
  double recall() const { return tp + fn ? double(tp) / (tp + fn) : 0.0; }
  double f1() const { const double p = precision(), r = recall(); return p + r > 0 ? 2 * p * r / (p + r) : 0.0; }
  double iou() const { return tp + fp + fn ? double(tp) / (tp + fp + fn) : 0.0; }
};

// `changed[m]` holds the (scan, index) pairs predicted changed in mission m.
PointScore score_points(const lista::MissionSet& missions, const lista::io::GroundTruth& truth,
                        const std::vector<std::set<std::pair<uint32_t, uint32_t>>>& changed);
