// 2-D oriented rectangles on the floor: object footprints, structure and the
// robot's corridor. Placement keeps footprints apart, so no two objects
// interpenetrate.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace lista::sim {

struct Footprint {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d half = Eigen::Vector2d::Zero();  // half sizes along the rotated axes
  double yaw = 0.0;
};

// Separating-axis test; `margin` inflates both rectangles (gap they must keep).
bool overlaps(const Footprint& a, const Footprint& b, double margin = 0.0);

bool overlaps_any(const Footprint& a, const std::vector<Footprint>& others, double margin = 0.0);

// Footprint of a thin segment p->q with half width w (walls, route corridor).
Footprint segment_footprint(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double w);

}  // namespace lista::sim
