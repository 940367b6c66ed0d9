// How much of one object's view lies on another's surface, fair to sparse
// scanners.
//
// A point-to-point test ("within `inlier` of a point of the other view")
// measures the other view's sampling as much as the fit: a 16-beam scanner's
// rings lie 2 degrees apart (10 cm at 3 m), so a point of one mission's view
// that falls between the other mission's rings is several centimetres from
// every point of it however well the two views are registered. Here such a
// point also counts when the other view's points around it (within `gap`)
// span a surface (not one ring: a line), surround it (it is inside their
// spread, not beyond the object's edge) and it lies within inlier / 2 of
// their plane. Dense views are judged as before: their points are within
// `inlier` of one another anyway.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

namespace lista::objreg {

struct SurfaceShareConfig {
  double voxel = 0.04;    // m: both views downsampled first (0 = none)
  double inlier = 0.05;   // m: a point this near a point of the other view is on its surface
  double gap = 0.15;      // m: the widest sampling gap bridged (0 = point test only)
  int max_points = 2000;  // at most this many points of each view judged (strided); 0 = all
};

struct SurfaceShares {
  double source = 0.0;  // share of the source's points, moved by t, on the target's surface
  double target = 0.0;  // share of the target's points, moved by t^-1, on the source's surface
};

// How well one rigid object explains both views, in [0, 1]: 0.75 x the
// larger share + 0.25 x the smaller. The view with the better-explained
// points is mostly the smaller or partial one: it must fit; the other must
// fit at least in part.
inline double shape_fit(double source_share, double target_share) {
  return 0.75 * std::max(source_share, target_share) + 0.25 * std::min(source_share, target_share);
}

// Both shares of a registered pair (0 for an empty view); p_target = t *
// p_source.
SurfaceShares surface_shares(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                             const Eigen::Isometry3d& t, const SurfaceShareConfig& cfg);

}  // namespace lista::objreg
