#include "surface_patch.hpp"

#include <lista_geometry/voxel_key.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace lista::filter {

Patch patch_of(const std::vector<std::pair<uint64_t, Eigen::Vector3f>>& keyed, uint64_t key) {
  const Eigen::Vector3i at = geometry::voxel_of_key(key);
  std::vector<Eigen::Vector3d> pts;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int in_cell = 0;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const uint64_t nb = geometry::voxel_key(at + Eigen::Vector3i(dx, dy, dz));
        auto it = std::lower_bound(keyed.begin(), keyed.end(), nb,
                                   [](const auto& e, uint64_t k) { return e.first < k; });
        for (; it != keyed.end() && it->first == nb; ++it) {
          pts.push_back(it->second.cast<double>());
          if (nb == key) {
            centre += pts.back();
            ++in_cell;
          }
        }
      }
  Patch patch;
  if (in_cell == 0 || pts.size() < 5) return patch;
  patch.centre = centre / double(in_cell);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / double(pts.size()));
  patch.normal = eig.eigenvectors().col(0);
  if (patch.normal.dot(patch.centre) > 0) patch.normal = -patch.normal;  // toward the sensor that saw it
  // Flat, and spread both ways: the points of one ring on the floor form a
  // line whose noise runs along the rays, and a plane through it would be
  // tilted towards the sensor. Seen edge-on, which side it was seen from is
  // not clear either.
  const Eigen::Vector3d view = patch.centre.normalized();
  patch.valid = eig.eigenvalues()(0) < 0.05 * eig.eigenvalues()(1) && eig.eigenvalues()(1) > 0.03 * 0.03 &&
                std::abs(view.dot(patch.normal)) > 0.1;
  return patch;
}

}  // namespace lista::filter
