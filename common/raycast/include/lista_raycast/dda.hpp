// 3D digital differential analyser (Amanatides & Woo, 1987): the voxels a
// straight segment crosses, in order. Header-only so the per-voxel visitor is
// inlined into the hot loop of each backend.
#pragma once

#include <lista_raycast/voxel.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <limits>

namespace lista::raycast {

// Number of voxels walk_ray(from, to) visits: the L1 distance between the two voxels.
inline int ray_voxels(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  return (voxel_of(to) - voxel_of(from)).cwiseAbs().sum();
}

// One Amanatides-Woo walk: the voxel holding `from`, stepped towards `to`.
// Plain scalars and a branch-free step keep the walk in registers: the axis
// to step is data-dependent and would mispredict as a branch.
struct DdaWalk {
  int x, y, z;
  int steps;  // L1 distance between the start and end voxels: the walk's length
  int sx, sy, sz;
  double tx, ty, tz, dx, dy, dz;  // next boundary crossing and spacing, per axis

  DdaWalk(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
    const Voxel v = voxel_of(from);
    x = v.x(), y = v.y(), z = v.z();
    steps = ray_voxels(from, to);
    const Eigen::Vector3d d = to - from;
    axis(d.x(), from.x(), x, sx, tx, dx);
    axis(d.y(), from.y(), y, sy, ty, dy);
    axis(d.z(), from.z(), z, sz, tz, dz);
  }

  Voxel voxel() const { return Voxel(x, y, z); }

  // Moves into the next voxel the segment crosses; ties go to the later axis
  // among the smallest (y before x, z before y), as they always have.
  inline void advance() {
    const bool mx = tx < ty && tx < tz;
    const bool my = !mx && ty < tz;
    const bool mz = !mx && !my;
    x += mx ? sx : 0;
    y += my ? sy : 0;
    z += mz ? sz : 0;
    tx += mx ? dx : 0.0;
    ty += my ? dy : 0.0;
    tz += mz ? dz : 0.0;
  }

 private:
  static void axis(double d, double from, int v, int& step, double& t_max, double& t_delta) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (d > 0) {
      step = 1;
      t_delta = 1.0 / d;
      t_max = (v + 1 - from) * t_delta;
    } else if (d < 0) {
      step = -1;
      t_delta = -1.0 / d;
      t_max = (from - v) * t_delta;
    } else {
      step = 0;
      t_delta = inf;
      t_max = inf;
    }
  }
};

// Visits every voxel from the one holding `from` up to, but NOT including, the
// one holding `to` (both in index units). The end voxel is left out because it
// holds the return, which is a hit, not free space (OctoMap's computeRayKeys
// does the same). Returns the number of voxels visited. The walk is bounded by
// the L1 distance between the two voxels, so rounding can never loop forever.
template <class Visit>
inline uint32_t walk_ray(const Eigen::Vector3d& from, const Eigen::Vector3d& to, Visit&& visit) {
  DdaWalk w(from, to);
  for (int n = 0; n < w.steps; ++n) {
    visit(w.voxel());
    w.advance();
  }
  return static_cast<uint32_t>(w.steps);
}

// The voxels of walk_ray(from, to), walked backwards: from the voxel after the
// one holding `to` back to the one holding `from` (included), for as long as
// `visit` returns true. Returns the number of voxels visited. Lets a beam stop
// once it meets free space its scan has already counted: beams from one origin
// converge, so the rest of its path is (all but a few voxels) already covered.
template <class Visit>
inline uint32_t walk_ray_back(const Eigen::Vector3d& from, const Eigen::Vector3d& to, Visit&& visit) {
  DdaWalk w(to, from);
  for (int n = 0; n < w.steps; ++n) {
    w.advance();
    if (!visit(w.voxel())) return static_cast<uint32_t>(n + 1);
  }
  return static_cast<uint32_t>(w.steps);
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

// How far short of its return a hitting beam stops being free: `margin`, or
// for a beam going down (-z) the stretch where it runs within `graze_height`
// above the return's height (graze_height / sin(descent)), at most
// `graze_max`, if longer. A beam that drops no more than graze_height over
// its whole length runs level at the sensor's height, into a wall or a
// thing, not along a floor: it keeps `margin` (else a 1 mm dip would cost
// it graze_max of free space). All three in the units of origin and hit.
inline double beam_margin(const Eigen::Vector3d& origin, const Eigen::Vector3d& hit, double margin,
                          double graze_height, double graze_max) {
  if (graze_height <= 0 || graze_max <= margin) return margin;
  const Eigen::Vector3d d = hit - origin;
  const double len = d.norm();
  const double drop = -d.z();  // len * sin(descent)
  if (drop <= graze_height || len <= 0) return margin;
  const double graze = drop * graze_max >= graze_height * len ? graze_height * len / drop : graze_max;
  return std::max(margin, graze);
}

// The end of the free part of a beam that hits: `margin` (in the units of
// origin and hit) short of the return, or the origin for beams shorter than
// that.
inline Eigen::Vector3d free_end(const Eigen::Vector3d& origin, const Eigen::Vector3d& hit, double margin) {
  if (margin <= 0) return hit;
  const Eigen::Vector3d d = hit - origin;
  const double len = d.norm();
  return len <= margin ? origin : Eigen::Vector3d(origin + d * ((len - margin) / len));
}

}  // namespace lista::raycast
