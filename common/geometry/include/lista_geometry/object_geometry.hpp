// Object geometry shared by the plugins that compare objects: how far apart
// two boxes are, and a yaw-invariant footprint. Header only.
#pragma once

#include <lista/objects.hpp>
#include <lista_geometry/bounding_rectangle.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <vector>

namespace lista::geometry {

// Distance between the axis-aligned boxes of two objects; 0 when they touch.
inline float box_gap(const Object& a, const Object& b) {
  const Eigen::Vector3f d = (a.bbox_min - b.bbox_max).cwiseMax(b.bbox_min - a.bbox_max).cwiseMax(0.f);
  return d.norm();
}

// Sides of the footprint's minimum-perimeter rectangle (bounding_rectangle.hpp),
// larger first: the footprint of an object whatever its yaw, lined up with
// the faces of a box even when a view shows only one or two of them. Points
// that span no area fall back to the extents along the principal axes of
// their horizontal spread. Zero for fewer than three points.
inline Eigen::Vector2f horizontal_extents(const std::vector<Eigen::Vector3f>& pts) {
  if (pts.size() < 3) return Eigen::Vector2f::Zero();
  if (const BoundingRectangle r = min_perimeter_rectangle(pts); r.valid)
    return {float(r.long_side), float(r.short_side)};
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : pts) mean += p.head<2>().cast<double>();
  mean /= double(pts.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : pts) {
    const Eigen::Vector2d d = p.head<2>().cast<double>() - mean;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
  double lo[2] = {1e30, 1e30}, hi[2] = {-1e30, -1e30};
  for (const auto& p : pts)
    for (int k = 0; k < 2; ++k) {
      const double t = (p.head<2>().cast<double>() - mean).dot(es.eigenvectors().col(k));
      lo[k] = std::min(lo[k], t), hi[k] = std::max(hi[k], t);
    }
  const float e0 = float(hi[0] - lo[0]), e1 = float(hi[1] - lo[1]);
  return {std::max(e0, e1), std::min(e0, e1)};
}

}  // namespace lista::geometry
