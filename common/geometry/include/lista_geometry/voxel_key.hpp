// Voxel coordinates packed into one 64-bit hash key, header only: 21 bits
// per axis, offset so that +-2^20 cells (+-100 km at 0.1 m) fit.
#pragma once

#include <lista/error.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <string>

namespace lista::geometry {

// Cells per axis either side of the origin that a key holds.
inline constexpr int64_t kVoxelKeyReach = int64_t(1) << 20;

inline uint64_t voxel_key(const Eigen::Vector3i& v) {
  constexpr int64_t off = kVoxelKeyReach;
  return (uint64_t(v.x() + off) << 42) | (uint64_t(v.y() + off) << 21) | uint64_t(v.z() + off);
}

// The voxel a key was packed from (keys sort by x, then y, then z).
inline Eigen::Vector3i voxel_of_key(uint64_t key) {
  constexpr int64_t off = kVoxelKeyReach;
  constexpr uint64_t mask = (uint64_t(1) << 21) - 1;
  return Eigen::Vector3i(int(int64_t((key >> 42) & mask) - off), int(int64_t((key >> 21) & mask) - off),
                         int(int64_t(key & mask) - off));
}

// The key of the voxel of edge `cell` holding p.
inline uint64_t voxel_key_of(const Eigen::Vector3d& p, double cell) {
  return voxel_key((p / cell).array().floor().cast<int>());
}

// The voxel of `p` in a grid of edge 1/inv, with room left for its
// neighbours' keys; a point beyond that reach is an error naming `index`.
inline Eigen::Vector3i voxel_in_reach(const Eigen::Vector3f& p, double inv, size_t index) {
  const Eigen::Vector3d c = (p.cast<double>() * inv).array().floor();
  if ((c.array().abs() >= double(kVoxelKeyReach - 2)).any())
    throw Error("point " + std::to_string(index) + " is too far from the origin for the voxel grid");
  return c.cast<int>();
}

}  // namespace lista::geometry
