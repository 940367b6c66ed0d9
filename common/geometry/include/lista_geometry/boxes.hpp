// Axis-aligned boxes in the common frame, and a mission's points inside
// any of several (what segment.complete and history.static work on). Header
// only.
#pragma once

#include <lista/missions.hpp>
#include <lista/parallel.hpp>
#include <lista/points.hpp>

#include <Eigen/Core>

#include <limits>
#include <vector>

namespace lista::geometry {

// Empty (inverted) until extended.
struct Box {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  bool contains(const Eigen::Vector3f& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
  void extend(const Box& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  Box grown(float xy, float z_down, float z_up) const {
    Box b = *this;
    b.lo -= Eigen::Vector3f(xy, xy, z_down);
    b.hi += Eigen::Vector3f(xy, xy, z_up);
    return b;
  }
};

// Every point of `mission` inside any of `boxes`, in the common frame, in
// scan then file order (whatever the thread count).
inline PointSet points_in_boxes(const Mission& mission, const std::vector<Box>& boxes, int threads) {
  if (boxes.empty()) return {};
  Box all;
  for (const Box& b : boxes) all.extend(b);
  std::vector<PointSet> per_scan(mission.scans.size());
  parallel_for(mission.scans.size(), threads, [&](size_t s) {
    const Scan& scan = mission.scans[s];
    if (!scan.points) return;
    const Eigen::Affine3f T = mission.sensor_to_common(s).cast<float>();
    const PointSet& src = *scan.points;
    for (size_t i = 0; i < src.size(); ++i) {
      const Eigen::Vector3f p = T * src.xyz[i];
      if (!all.contains(p)) continue;
      for (const Box& b : boxes)
        if (b.contains(p)) {
          per_scan[s].push_back_from(src, i);
          per_scan[s].xyz.back() = p;
          break;
        }
    }
  });
  size_t total = 0;
  for (const PointSet& s : per_scan) total += s.size();
  PointSet out;
  out.reserve(total);
  for (const PointSet& s : per_scan) out.append(s);
  return out;
}

}  // namespace lista::geometry
