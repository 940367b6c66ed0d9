// The voxel grid both volumetric backends use: voxel (i, j, k) covers
// [i*r, (i+1)*r) x [j*r, (j+1)*r) x [k*r, (k+1)*r) in the common frame, which is
// OctoMap's convention (key = floor(x / r) + 2^15), so the two backends
// classify every point against the same cells.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace lista::raycast {

using Voxel = Eigen::Vector3i;

// Voxel of a point given in index units (world / resolution).
inline Voxel voxel_of(const Eigen::Vector3d& p_index) {
  return Voxel(static_cast<int>(std::floor(p_index.x())), static_cast<int>(std::floor(p_index.y())),
               static_cast<int>(std::floor(p_index.z())));
}

// Log-odds <-> probability.
inline float logodds(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }
inline double probability(float l) { return 1.0 - 1.0 / (1.0 + std::exp(static_cast<double>(l))); }

}  // namespace lista::raycast
