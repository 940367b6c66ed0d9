// Embree 3 ray casting against labelled triangle meshes. Embree headers stay
// in raycaster.cpp.
#pragma once

#include "mesh.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace lista::sim {

struct Hit {
  float t = -1.0f;  // distance along the unit ray; < 0 = no hit
  uint32_t label = 0;
  float reflectivity = 0.0f;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();  // unit geometric normal
};

// Immutable after commit(); intersect() is thread-safe.
class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  void add(const TriMesh& mesh, const Eigen::Isometry3f& pose, uint32_t label, float reflectivity);
  void commit();
  bool empty() const { return labels_.empty(); }  // triangles_ is cleared by commit()
  Hit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float tmin,
                float tmax) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<Eigen::Vector3f> vertices_;
  std::vector<Eigen::Vector3i> triangles_;
  std::vector<uint32_t> labels_;  // per triangle
  std::vector<float> reflectivity_;
};

}  // namespace lista::sim
