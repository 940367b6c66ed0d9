// Whether a mission was scanned from stop-and-go stations: its scans stand
// farther apart (median step between consecutive scans) than their points
// reach (median horizontal range, every 64th point), or it is one scan.
// Each station then sees its own part of the site. Header only;
// align.posegraph judges such a mission's scan pairs on the whole-map
// overlap gate, the volumetric stages take one look each as evidence
// (docs/alignment.md and docs/volumetric.md, "Stations").
#pragma once

#include <lista/missions.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace lista::geometry {

inline bool scanned_from_stations(const Mission& mission) {
  std::vector<double> steps, ranges;
  const Scan* before = nullptr;
  size_t held = 0;
  for (const Scan& scan : mission.scans) {
    if (!scan.points || scan.points->empty()) continue;  // a dropout is stepped over
    ++held;
    if (before) steps.push_back((scan.pose.translation() - before->pose.translation()).norm());
    before = &scan;
    const auto& xyz = scan.points->xyz;
    for (size_t j = 0; j < xyz.size(); j += 64) ranges.push_back(std::hypot(double(xyz[j].x()), double(xyz[j].y())));
  }
  if (held == 1) return true;
  if (steps.empty() || ranges.empty()) return false;
  return median(steps) > median(ranges);
}

}  // namespace lista::geometry
