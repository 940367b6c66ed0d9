#include "seen_through.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lista::align {
namespace {

// The bin of direction p (azimuth columns, elevation rows); false at the origin.
bool bin_of(const Eigen::Vector3d& p, int columns, int rows, int& column, int& row) {
  const double r = p.norm();
  if (r < 1e-6) return false;
  column = std::min(columns - 1, int((std::atan2(p.y(), p.x()) + M_PI) / (2.0 * M_PI) * columns));
  row = std::min(rows - 1, int((std::asin(std::clamp(p.z() / r, -1.0, 1.0)) + M_PI / 2.0) / M_PI * rows));
  return true;
}

}  // namespace

SeenThrough::SeenThrough(const Cloud& points)
    : nearest_(size_t(kColumns) * kRows, std::numeric_limits<float>::infinity()) {
  for (const auto& p : points) {
    int column = 0, row = 0;
    const Eigen::Vector3d q = p.cast<double>();
    if (!bin_of(q, kColumns, kRows, column, row)) continue;
    float& nearest = nearest_[size_t(row) * kColumns + size_t(column)];
    nearest = std::min(nearest, float(q.norm()));
  }
}

double SeenThrough::share_in_front(const Cloud& points, const Eigen::Isometry3d& sensor_T_points) const {
  size_t known = 0, in_front = 0;
  const size_t stride = std::max<size_t>(1, points.size() / kMaxPoints);
  for (size_t i = 0; i < points.size(); i += stride) {
    const Eigen::Vector3d q = sensor_T_points * points[i].cast<double>();
    int column = 0, row = 0;
    if (!bin_of(q, kColumns, kRows, column, row)) continue;
    // The nearest return about the direction: a point at a depth edge is
    // not taken for one in front of the background beside it.
    float nearest = std::numeric_limits<float>::infinity();
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int r = row + dr, c = (column + dc + kColumns) % kColumns;
        if (r >= 0 && r < kRows) nearest = std::min(nearest, nearest_[size_t(r) * kColumns + size_t(c)]);
      }
    if (!std::isfinite(nearest)) continue;
    ++known;
    if (q.norm() < nearest - std::max(0.5, 0.05 * double(nearest))) ++in_front;
  }
  return known ? double(in_front) / double(known) : 0.0;
}

}  // namespace lista::align
