#include "footprint.hpp"

#include <cmath>

namespace lista::sim {

bool overlaps(const Footprint& a, const Footprint& b, double margin) {
  const Eigen::Vector2d ha = a.half + Eigen::Vector2d::Constant(0.5 * margin);
  const Eigen::Vector2d hb = b.half + Eigen::Vector2d::Constant(0.5 * margin);
  const Eigen::Vector2d axes[4] = {{std::cos(a.yaw), std::sin(a.yaw)}, {-std::sin(a.yaw), std::cos(a.yaw)},
                                   {std::cos(b.yaw), std::sin(b.yaw)}, {-std::sin(b.yaw), std::cos(b.yaw)}};
  const Eigen::Vector2d d = b.centre - a.centre;
  for (const auto& axis : axes) {
    const double ra = ha.x() * std::abs(axes[0].dot(axis)) + ha.y() * std::abs(axes[1].dot(axis));
    const double rb = hb.x() * std::abs(axes[2].dot(axis)) + hb.y() * std::abs(axes[3].dot(axis));
    if (std::abs(d.dot(axis)) > ra + rb) return false;  // separating axis found
  }
  return true;
}

bool overlaps_any(const Footprint& a, const std::vector<Footprint>& others, double margin) {
  for (const auto& o : others)
    if (overlaps(a, o, margin)) return true;
  return false;
}

Footprint segment_footprint(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double w) {
  Footprint f;
  f.centre = 0.5 * (p + q);
  f.half = Eigen::Vector2d(0.5 * (q - p).norm() + w, w);
  f.yaw = std::atan2(q.y() - p.y(), q.x() - p.x());
  return f;
}

}  // namespace lista::sim
