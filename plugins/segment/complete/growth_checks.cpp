#include "growth_checks.hpp"

#include <lista_geometry/object_geometry.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <cmath>
#include <cstdio>
#include <unordered_set>

namespace lista::segment::completion {

void add_points(Object& o, const PointSet& cloud, const std::vector<uint32_t>& add) {
  const bool known = o.points.has_changed_against();
  const uint8_t bits = o.points.changed_against_all();
  std::vector<uint8_t> against = std::move(o.points.changed_against);
  o.points.changed_against.clear();
  for (uint32_t i : add) o.points.push_back_from(cloud, i);
  if (known) {
    against.resize(o.points.size(), bits);
    o.points.changed_against = std::move(against);
  }
}

Eigen::Vector3f shape_of(const PointSet& own, const std::vector<uint32_t>& extra, const PointSet& cloud,
                         float floor, float min_z) {
  std::vector<Eigen::Vector3f> pts;
  for (const auto& p : own.xyz)
    if (p.z() >= min_z) pts.push_back(p);
  for (uint32_t i : extra) pts.push_back(cloud.xyz[i]);
  if (pts.size() < 3) return Eigen::Vector3f::Zero();
  float top = std::numeric_limits<float>::lowest();
  for (const auto& p : pts) top = std::max(top, p.z());
  const Eigen::Vector2f e = geometry::horizontal_extents(pts);
  return {top - floor, e[0], e[1]};
}

std::string format_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", v);
  return text;
}

std::string shape_note(const Eigen::Vector3f& s) {
  return format_number(s[0]) + " x " + format_number(s[1]) + " x " + format_number(s[2]) + " m";
}

std::string leak_note(const Growth& g) {
  return format_number(double(g.leaks) / double(std::max<size_t>(g.voxels, 1)));
}

bool same_shape(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const CompletionConfig& c, double strictness) {
  for (int k = 0; k < 3; ++k) {
    const double allowed = strictness * std::max(c.shape_slack, c.shape_tolerance * std::max(a[k], b[k]));
    if (std::abs(a[k] - b[k]) > allowed) return false;
  }
  return true;
}

std::vector<uint32_t> base_points(const Object& o, const LocalCloud& cloud, const Floor& floor,
                                  const Owners& owned) {
  std::unordered_set<uint64_t> columns;
  auto column = [](float x, float y) {
    return voxel_key(Eigen::Vector3i(int(std::floor(x * 20.f)), int(std::floor(y * 20.f)), 0));
  };
  for (const auto& p : o.points.xyz)
    if (p.z() < o.bbox_min.z() + 0.15f) {
      const int cx = int(std::floor(p.x() * 20.f)), cy = int(std::floor(p.y() * 20.f));
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) columns.insert(voxel_key(Eigen::Vector3i(cx + dx, cy + dy, 0)));
    }
  std::vector<uint32_t> added;
  const float top = o.bbox_min.z() + 0.05f;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const auto& p = cloud.points.xyz[i];
    if (p.z() < floor.clear_z || p.z() > top || !columns.count(column(p.x(), p.y()))) continue;
    if (owned.count(point_key(cloud.points.scan[i], cloud.points.index[i]))) continue;
    added.push_back(uint32_t(i));
  }
  return added;
}

int surface_sides(const Object& o, const LocalCloud& own, float ring, float tol) {
  std::vector<float> z;
  z.reserve(o.points.size());
  for (const auto& p : o.points.xyz) z.push_back(p.z());
  const float zc = geometry::median(z);
  constexpr float kColumn = 0.1f;
  auto column = [&](float v) { return int(std::floor(v / kColumn)); };
  const int ix0 = column(o.bbox_min.x()), ix1 = column(o.bbox_max.x());
  const int iy0 = column(o.bbox_min.y()), iy1 = column(o.bbox_max.y());
  const int w = std::max(1, int(std::ceil(ring / kColumn)));
  // Side of column (x, y): 0 -x, 1 +x, 2 -y, 3 +y; -1 inside the box, in a
  // corner or beyond the strips.
  auto side = [&](int x, int y) {
    const bool in_x = x >= ix0 && x <= ix1, in_y = y >= iy0 && y <= iy1;
    if (in_y && x < ix0 && x >= ix0 - w) return 0;
    if (in_y && x > ix1 && x <= ix1 + w) return 1;
    if (in_x && y < iy0 && y >= iy0 - w) return 2;
    if (in_x && y > iy1 && y <= iy1 + w) return 3;
    return -1;
  };
  const size_t cells[4] = {size_t(w) * size_t(iy1 - iy0 + 1), size_t(w) * size_t(iy1 - iy0 + 1),
                           size_t(w) * size_t(ix1 - ix0 + 1), size_t(w) * size_t(ix1 - ix0 + 1)};
  std::unordered_set<uint64_t> held[4];
  for (const auto& p : own.points.xyz) {
    if (std::abs(p.z() - zc) > tol) continue;
    const int x = column(p.x()), y = column(p.y()), k = side(x, y);
    if (k >= 0) held[k].insert(voxel_key(Eigen::Vector3i(x, y, 0)));
  }
  int sides = 0;
  for (int k = 0; k < 4; ++k) sides += 2 * held[k].size() >= cells[k];
  return sides;
}

}  // namespace lista::segment::completion
