#include "mesh.hpp"

#include "rng.hpp"

#include <cmath>
#include <limits>

namespace lista::sim {

void TriMesh::append(const TriMesh& other, const Eigen::Isometry3f& pose) {
  const int base = int(vertices.size());
  vertices.reserve(vertices.size() + other.vertices.size());
  for (const auto& v : other.vertices) vertices.push_back(pose * v);
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const auto& t : other.triangles) triangles.push_back(t + Eigen::Vector3i::Constant(base));
}

void TriMesh::add_box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  add_oriented_box(0.5f * (lo + hi), 0.5f * (hi - lo), 0.0f);
}

void TriMesh::add_oriented_box(const Eigen::Vector3f& centre, const Eigen::Vector3f& half, float yaw) {
  const Eigen::Matrix3f r = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  const int base = int(vertices.size());
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3f corner((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                                 (i & 4) ? half.z() : -half.z());
    vertices.push_back(centre + r * corner);
  }
  // Two triangles per face; winding does not matter to the ray caster.
  static const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                  {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
  for (const auto& f : faces) {
    triangles.emplace_back(base + f[0], base + f[1], base + f[2]);
    triangles.emplace_back(base + f[0], base + f[2], base + f[3]);
  }
}

void TriMesh::add_cylinder(const Eigen::Vector3f& base_centre, float radius, float height, int segments) {
  const int base = int(vertices.size());
  for (int k = 0; k < segments; ++k) {
    const float a = 2.0f * float(M_PI) * float(k) / float(segments);
    const Eigen::Vector3f rim(radius * std::cos(a), radius * std::sin(a), 0.0f);
    vertices.push_back(base_centre + rim);
    vertices.push_back(base_centre + rim + Eigen::Vector3f(0, 0, height));
  }
  const int bottom = int(vertices.size());
  vertices.push_back(base_centre);
  vertices.push_back(base_centre + Eigen::Vector3f(0, 0, height));
  for (int k = 0; k < segments; ++k) {
    const int a0 = base + 2 * k, a1 = a0 + 1;
    const int b0 = base + 2 * ((k + 1) % segments), b1 = b0 + 1;
    triangles.emplace_back(a0, b0, b1);
    triangles.emplace_back(a0, b1, a1);
    triangles.emplace_back(bottom, b0, a0);
    triangles.emplace_back(bottom + 1, a1, b1);
  }
}

void TriMesh::add_wheel(const Eigen::Vector3f& centre, float radius, float width, int segments) {
  TriMesh cylinder;
  cylinder.add_cylinder(Eigen::Vector3f(0, 0, -0.5f * width), radius, width, segments);
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.linear() = Eigen::AngleAxisf(float(M_PI) / 2, Eigen::Vector3f::UnitY()).toRotationMatrix();
  pose.translation() = centre;
  append(cylinder, pose);
}

void TriMesh::bounds(Eigen::Vector3f& lo, Eigen::Vector3f& hi) const {
  lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  hi = -lo;
  for (const auto& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  if (vertices.empty()) lo = hi = Eigen::Vector3f::Zero();
}

uint64_t TriMesh::geometry_key() const {
  uint64_t h = hash_combine(vertices.size(), triangles.size());
  for (const auto& v : vertices)
    for (int k = 0; k < 3; ++k) h = hash_combine(h, uint64_t(int64_t(std::lround(double(v[k]) * 1e4))));
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) h = hash_combine(h, uint64_t(t[k]));
  return h;
}

}  // namespace lista::sim
