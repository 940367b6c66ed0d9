#include "look_alikes.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace lista::sim {
namespace {

using Vec = Eigen::Vector3f;

// Squared distance from p to triangle abc: the closest point by Voronoi
// region of the triangle (vertex, edge or face).
float squared_distance_to_triangle(const Vec& p, const Vec& a, const Vec& b, const Vec& c) {
  const Vec ab = b - a, ac = c - a, ap = p - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.squaredNorm();
  const Vec bp = p - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.squaredNorm();
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).squaredNorm();
  const Vec cp = p - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.squaredNorm();
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).squaredNorm();
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).squaredNorm();
  const float denom = 1.0f / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).squaredNorm();
}

// Triangles binned in a uniform grid of cells at least `reach` wide, so the
// triangles within `reach` of a point lie in the 3 x 3 x 3 cells around it.
class TriangleGrid {
 public:
  TriangleGrid(const TriMesh& mesh, float reach) : mesh_(mesh) {
    Vec hi;
    mesh.bounds(lo_, hi);
    cell_ = std::max(reach, (hi - lo_).maxCoeff() / 48.0f);
    for (int t = 0; t < int(mesh.triangles.size()); ++t) {
      Vec tlo = Vec::Constant(1e30f), thi = -tlo;
      for (int k = 0; k < 3; ++k) {
        tlo = tlo.cwiseMin(mesh.vertices[size_t(mesh.triangles[size_t(t)][k])]);
        thi = thi.cwiseMax(mesh.vertices[size_t(mesh.triangles[size_t(t)][k])]);
      }
      const Eigen::Vector3i c0 = cell_of(tlo), c1 = cell_of(thi);
      for (int x = c0.x(); x <= c1.x(); ++x)
        for (int y = c0.y(); y <= c1.y(); ++y)
          for (int z = c0.z(); z <= c1.z(); ++z) cells_[key(x, y, z)].push_back(t);
    }
  }

  bool any_within(const Vec& p, float reach) const {
    const float r2 = reach * reach;
    const Eigen::Vector3i c = cell_of(p);
    for (int x = c.x() - 1; x <= c.x() + 1; ++x)
      for (int y = c.y() - 1; y <= c.y() + 1; ++y)
        for (int z = c.z() - 1; z <= c.z() + 1; ++z) {
          const auto it = cells_.find(key(x, y, z));
          if (it == cells_.end()) continue;
          for (int t : it->second) {
            const Eigen::Vector3i& tri = mesh_.triangles[size_t(t)];
            if (squared_distance_to_triangle(p, mesh_.vertices[size_t(tri[0])], mesh_.vertices[size_t(tri[1])],
                                             mesh_.vertices[size_t(tri[2])]) <= r2)
              return true;
          }
        }
    return false;
  }

 private:
  Eigen::Vector3i cell_of(const Vec& p) const { return ((p - lo_) / cell_).array().floor().cast<int>(); }
  static uint64_t key(int x, int y, int z) {
    // Offsets keep the neighbours of border cells (-1) non-negative.
    return (uint64_t(x + 2) << 42) | (uint64_t(y + 2) << 21) | uint64_t(z + 2);
  }
  const TriMesh& mesh_;
  Vec lo_;
  float cell_ = 1.0f;
  std::unordered_map<uint64_t, std::vector<int>> cells_;
};

// Every point of a's surface on a barycentric lattice no coarser than
// `spacing` is within `tolerance` of b's surface.
bool one_way_within(const TriMesh& a, const TriMesh& b, float tolerance, float spacing) {
  const TriangleGrid grid(b, tolerance);
  for (const auto& t : a.triangles) {
    const Vec &p0 = a.vertices[size_t(t[0])], &p1 = a.vertices[size_t(t[1])], &p2 = a.vertices[size_t(t[2])];
    const float longest = std::max({(p1 - p0).norm(), (p2 - p1).norm(), (p0 - p2).norm()});
    const int m = std::max(1, int(std::ceil(longest / spacing)));
    for (int i = 0; i <= m; ++i)
      for (int j = 0; i + j <= m; ++j) {
        const Vec p = p0 + (p1 - p0) * (float(i) / float(m)) + (p2 - p0) * (float(j) / float(m));
        if (!grid.any_within(p, tolerance)) return false;
      }
  }
  return true;
}

struct Box {
  Vec lo, hi;
  explicit Box(const TriMesh& m) { m.bounds(lo, hi); }
  // Necessary for surfaces within `tolerance`: every bound within it.
  bool near(const Box& o, float tolerance) const {
    return (lo - o.lo).cwiseAbs().maxCoeff() <= tolerance && (hi - o.hi).cwiseAbs().maxCoeff() <= tolerance;
  }
};

bool surfaces_within(const TriMesh& a, const Box& abox, const TriMesh& b, const Box& bbox, float tolerance) {
  if (a.empty() || b.empty()) return a.empty() && b.empty();
  if (!abox.near(bbox, tolerance)) return false;  // most pairs stop here
  const float spacing = std::max(0.5f * tolerance, 1e-4f);
  return one_way_within(a, b, tolerance, spacing) && one_way_within(b, a, tolerance, spacing);
}

}  // namespace

bool surfaces_within(const TriMesh& a, const TriMesh& b, float tolerance) {
  return surfaces_within(a, Box(a), b, Box(b), tolerance);
}

void share_ids_of_look_alikes(std::vector<Shape>& shapes, float tolerance) {
  if (tolerance <= 0.0f) return;
  std::vector<Box> boxes;
  for (const auto& s : shapes) boxes.emplace_back(s.mesh);
  std::vector<size_t> kept;  // shapes that kept their own id, in pool order
  for (size_t i = 0; i < shapes.size(); ++i) {
    bool joined = false;
    for (size_t k : kept) {
      if (shapes[k].id == shapes[i].id) {  // already one geometry
        joined = true;
        break;
      }
      if (surfaces_within(shapes[k].mesh, boxes[k], shapes[i].mesh, boxes[i], tolerance)) {
        shapes[i].id = shapes[k].id;
        joined = true;
        break;
      }
    }
    if (!joined) kept.push_back(i);
  }
}

}  // namespace lista::sim
