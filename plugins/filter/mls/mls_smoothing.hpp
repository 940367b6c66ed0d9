// Moving Least Squares smoothing (PCL) that keeps one output per input point:
// each point is projected onto the local polynomial surface fitted to its
// neighbours within `radius`. Only positions change; provenance and the
// other channels stay with their point. A point PCL cannot fit (too few
// neighbours) keeps its original position, or is dropped if asked.
#pragma once

#include <lista/points.hpp>

namespace lista::filter {

struct MlsConfig {
  double radius = 0.1;          // m, neighbourhood of the fit
  int polynomial_order = 2;     // 1 = plane, 2 = quadric
  bool drop_unfitted = false;   // drop points with too few neighbours
};

// Returns the smoothed set; `fitted` (optional) gets how many points moved onto a fit.
PointSet mls_smooth(const PointSet& points, const MlsConfig& config, int threads, size_t* fitted = nullptr);

}  // namespace lista::filter
