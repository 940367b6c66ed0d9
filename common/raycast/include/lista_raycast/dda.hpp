// 3D digital differential analyser (Amanatides & Woo, 1987): the voxels a
// straight segment crosses, in order. Header-only so the per-voxel visitor is
// inlined into the hot loop of each backend.
#pragma once

#include <lista_raycast/voxel.hpp>

#include <cstdint>
#include <cstdlib>
#include <limits>

namespace lista::raycast {

// Visits every voxel from the one holding `from` up to, but NOT including, the
// one holding `to` (both in index units). The end voxel is left out because it
// holds the return, which is a hit, not free space (OctoMap's computeRayKeys
// does the same). Returns the number of voxels visited. The walk is bounded by
// the L1 distance between the two voxels, so rounding can never loop forever.
template <class Visit>
inline uint32_t walk_ray(const Eigen::Vector3d& from, const Eigen::Vector3d& to, Visit&& visit) {
  Voxel v = voxel_of(from);
  const Voxel end = voxel_of(to);
  const int steps = std::abs(end.x() - v.x()) + std::abs(end.y() - v.y()) + std::abs(end.z() - v.z());
  if (steps == 0) return 0;
  const Eigen::Vector3d d = to - from;
  int step[3];
  double t_max[3], t_delta[3];
  constexpr double inf = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] > 0) {
      step[k] = 1;
      t_delta[k] = 1.0 / d[k];
      t_max[k] = (v[k] + 1 - from[k]) * t_delta[k];
    } else if (d[k] < 0) {
      step[k] = -1;
      t_delta[k] = -1.0 / d[k];
      t_max[k] = (from[k] - v[k]) * t_delta[k];
    } else {
      step[k] = 0;
      t_delta[k] = inf;
      t_max[k] = inf;
    }
  }
  for (int n = 0; n < steps; ++n) {
    visit(v);
    const int a = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
    v[a] += step[a];
    t_max[a] += t_delta[a];
  }
  return static_cast<uint32_t>(steps);
}

// Clips a ray to `max_range` (index units; <= 0 means unlimited). Returns true
// if the return lies within range (its voxel is a hit); otherwise `end` is
// moved onto the range sphere and the whole ray is free space only.
inline bool clip_ray(const Eigen::Vector3d& origin, Eigen::Vector3d& end, double max_range) {
  if (max_range <= 0) return true;
  const Eigen::Vector3d d = end - origin;
  const double len2 = d.squaredNorm();
  if (len2 <= max_range * max_range) return true;
  end = origin + d * (max_range / std::sqrt(len2));
  return false;
}

// The end of the free part of a beam that hits: `margin` (index units) short
// of the return, or the origin for beams shorter than that.
inline Eigen::Vector3d free_end(const Eigen::Vector3d& origin, const Eigen::Vector3d& hit, double margin) {
  if (margin <= 0) return hit;
  const Eigen::Vector3d d = hit - origin;
  const double len = d.norm();
  return len <= margin ? origin : Eigen::Vector3d(origin + d * ((len - margin) / len));
}

}  // namespace lista::raycast
