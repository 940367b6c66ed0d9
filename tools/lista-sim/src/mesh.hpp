// Triangle meshes built from primitives; the geometry the ray caster sees.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace lista::sim {

struct TriMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;

  bool empty() const { return triangles.empty(); }
  void append(const TriMesh& other, const Eigen::Isometry3f& pose = Eigen::Isometry3f::Identity());
  // Axis-aligned box with corners lo and hi.
  void add_box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi);
  // Box given by centre, half sizes and yaw about z.
  void add_oriented_box(const Eigen::Vector3f& centre, const Eigen::Vector3f& half, float yaw);
  // Closed vertical cylinder standing on base_centre.
  void add_cylinder(const Eigen::Vector3f& base_centre, float radius, float height, int segments = 16);
  // Cylinder with its axis along x (wheels), centred at `centre`.
  void add_wheel(const Eigen::Vector3f& centre, float radius, float width, int segments = 12);
  void bounds(Eigen::Vector3f& lo, Eigen::Vector3f& hi) const;
  // A hash of the geometry (vertices rounded to 0.1 mm, triangles): equal
  // meshes give equal keys whatever parameters built them.
  uint64_t geometry_key() const;
};

}  // namespace lista::sim
