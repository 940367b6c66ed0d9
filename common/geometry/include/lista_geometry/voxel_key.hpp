// Voxel coordinates packed into one 64-bit hash key, header only: 21 bits
// per axis, offset so that +-2^20 cells (+-100 km at 0.1 m) fit.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace lista::geometry {

inline uint64_t voxel_key(const Eigen::Vector3i& v) {
  constexpr int64_t off = int64_t(1) << 20;
  return (uint64_t(v.x() + off) << 42) | (uint64_t(v.y() + off) << 21) | uint64_t(v.z() + off);
}

}  // namespace lista::geometry
