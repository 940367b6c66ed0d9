// Minimum-perimeter bounding rectangle of points projected onto the floor
// plane (x, y), over the edges of their 2-D convex hull (an optimal rectangle
// has a side on a hull edge). Man-made objects are mostly box-like: the
// tightest rectangle lines up with their faces even when a scan sees only one
// or two of them, where the principal axis of a partial view (an L of two
// faces of unequal length) does not. Perimeter, not area: the hull of an L is
// a right triangle, whose rectangles on a leg and on the hypotenuse have the
// same area, but the one on the legs is always shorter around.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace lista::objfeat {

struct BoundingRectangle {
  // Unit direction of the rectangle's longer side (the shorter side is the
  // perpendicular). Its sign is arbitrary; callers fix it.
  Eigen::Vector2d long_axis = Eigen::Vector2d::UnitX();
  double long_side = 0.0, short_side = 0.0;  // metres
  bool valid = false;  // false when the points span no area (fewer than 3 hull corners)
};

// O(n log n). Deterministic; rotating the input about z rotates the result
// (up to rounding, and up to which side is "longer" for a square).
BoundingRectangle min_perimeter_rectangle(const std::vector<Eigen::Vector3f>& xyz);

}  // namespace lista::objfeat
