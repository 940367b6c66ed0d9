// Minimum-perimeter bounding rectangle of points projected onto the floor
// plane (x, y), header only, over the edges of their 2-D convex hull (an optimal rectangle
// has a side on a hull edge). Man-made objects are mostly box-like: the
// tightest rectangle lines up with their faces even when a scan sees only one
// or two of them, where the principal axis of a partial view (an L of two
// faces of unequal length) does not. Perimeter, not area: the hull of an L is
// a right triangle, whose rectangles on a leg and on the hypotenuse have the
// same area, but the one on the legs is always shorter around.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace lista::geometry {

struct BoundingRectangle {
  // Unit direction of the rectangle's longer side (the shorter side is the
  // perpendicular). Its sign is arbitrary; callers fix it.
  Eigen::Vector2d long_axis = Eigen::Vector2d::UnitX();
  double long_side = 0.0, short_side = 0.0;  // metres
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  bool valid = false;  // false when the points span no area (fewer than 3 hull corners)

  // The four corners, counter-clockwise from the low end of both the long
  // axis and its perpendicular (-long_axis.y(), long_axis.x()).
  std::array<Eigen::Vector2d, 4> corners() const {
    const Eigen::Vector2d u = 0.5 * long_side * long_axis, v = 0.5 * short_side * Eigen::Vector2d(-long_axis.y(), long_axis.x());
    return {centre - u - v, centre + u - v, centre + u + v, centre - u + v};
  }
};

namespace detail {

inline double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Akl-Toussaint: points strictly inside the polygon of the extreme points in
// eight directions cannot be hull corners. One O(n) pass drops nearly all
// points of a dense object, so the O(n log n) sort sees few.
inline std::vector<Eigen::Vector2d> outside_extremes(std::vector<Eigen::Vector2d> p) {
  if (p.size() < 64) return p;
  const double c = std::sqrt(0.5);
  const Eigen::Vector2d dirs[8] = {{1, 0}, {c, c}, {0, 1}, {-c, c}, {-1, 0}, {-c, -c}, {0, -1}, {c, -c}};
  Eigen::Vector2d ext[8];
  double best[8];
  for (int k = 0; k < 8; ++k) ext[k] = p[0], best[k] = p[0].dot(dirs[k]);
  for (const auto& q : p)
    for (int k = 0; k < 8; ++k)
      if (const double v = q.dot(dirs[k]); v > best[k]) best[k] = v, ext[k] = q;
  // Extremes in order of direction angle are counter-clockwise; coincident
  // ones give no edge.
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> edges;
  for (int k = 0; k < 8; ++k)
    if (ext[k] != ext[(k + 1) % 8]) edges.emplace_back(ext[k], ext[(k + 1) % 8]);
  if (edges.size() < 3) return p;
  std::vector<Eigen::Vector2d> keep;
  for (const auto& q : p) {
    bool inside = true;
    for (const auto& [a, b] : edges)
      if (cross(a, b, q) <= 0) { inside = false; break; }
    if (!inside) keep.push_back(q);
  }
  return keep;
}

// Andrew's monotone chain; counter-clockwise, no collinear corners.
inline std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  p = outside_extremes(std::move(p));
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

}  // namespace detail

// O(n log n). Deterministic; rotating the input about z rotates the result
// (up to rounding, and up to which side is "longer" for a square).
inline BoundingRectangle min_perimeter_rectangle(const std::vector<Eigen::Vector3f>& xyz) {
  std::vector<Eigen::Vector2d> flat;
  flat.reserve(xyz.size());
  for (const auto& p : xyz) flat.emplace_back(p.x(), p.y());
  const std::vector<Eigen::Vector2d> hull = detail::convex_hull(std::move(flat));
  BoundingRectangle best;
  if (hull.size() < 3) return best;
  double best_perimeter = INFINITY;
  // The optimal rectangle has a side on a hull edge; hulls are small, so the
  // O(h^2) scan over edges is cheaper than maintaining calipers.
  for (size_t i = 0; i < hull.size(); ++i) {
    Eigen::Vector2d u = hull[(i + 1) % hull.size()] - hull[i];
    const double len = u.norm();
    if (len <= 0.0) continue;
    u /= len;
    const Eigen::Vector2d v(-u.y(), u.x());
    double lo_u = INFINITY, hi_u = -INFINITY, lo_v = INFINITY, hi_v = -INFINITY;
    for (const auto& q : hull) {
      const double a = q.dot(u), b = q.dot(v);
      lo_u = std::min(lo_u, a), hi_u = std::max(hi_u, a);
      lo_v = std::min(lo_v, b), hi_v = std::max(hi_v, b);
    }
    const double su = hi_u - lo_u, sv = hi_v - lo_v, perimeter = su + sv;  // half of it
    if (perimeter < best_perimeter * (1.0 - 1e-9)) {  // ties: the first edge in hull order wins
      best_perimeter = perimeter;
      best.valid = true;
      best.long_axis = su >= sv ? u : v;
      best.long_side = std::max(su, sv);
      best.short_side = std::min(su, sv);
      best.centre = 0.5 * (lo_u + hi_u) * u + 0.5 * (lo_v + hi_v) * v;
    }
  }
  return best;
}

}  // namespace lista::geometry
