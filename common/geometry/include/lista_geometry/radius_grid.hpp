// Points hashed by cells of a search radius, header only: every neighbour
// within the radius of a point lies in one of the 27 cells around its own.
// The grid holds indices into a point array the caller keeps and passes to
// each query.
#pragma once

#include <lista_geometry/voxel_key.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace lista::geometry {

class RadiusGrid {
 public:
  explicit RadiusGrid(float radius) : inv_(1.f / radius), r2_(radius * radius) {}

  void add(const Eigen::Vector3f& p, uint32_t i) { cells_[voxel_key(cell_of(p))].push_back(i); }

  // Calls f(i) for every indexed point xyz[i] within the radius of p.
  template <class F>
  void for_near(const std::vector<Eigen::Vector3f>& xyz, const Eigen::Vector3f& p, F&& f) const {
    visit(xyz, p, [&](uint32_t i) { f(i); return false; });
  }

  // Whether any indexed point lies within the radius of p.
  bool any_near(const std::vector<Eigen::Vector3f>& xyz, const Eigen::Vector3f& p) const {
    return visit(xyz, p, [](uint32_t) { return true; });
  }

 private:
  // Calls f on every point within the radius of p until f returns true;
  // says whether it did.
  template <class F>
  bool visit(const std::vector<Eigen::Vector3f>& xyz, const Eigen::Vector3f& p, F&& f) const {
    const Eigen::Vector3i c = cell_of(p);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(voxel_key(c + Eigen::Vector3i(dx, dy, dz)));
          if (it == cells_.end()) continue;
          for (uint32_t i : it->second)
            if ((xyz[i] - p).squaredNorm() <= r2_ && f(i)) return true;
        }
    return false;
  }

  Eigen::Vector3i cell_of(const Eigen::Vector3f& p) const { return (p * inv_).array().floor().cast<int>(); }
  float inv_, r2_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace lista::geometry
