// The object library: procedural furniture and yard objects with parameter
// variation, plus real meshes loaded from sweethome3d-furniture when present.
// Every shape stands on z = 0 in its own frame, centred in x and y, z up, in
// metres.
#pragma once

#include "mesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace lista::sim {

struct Shape {
  std::string id;         // unique per geometry, e.g. "chair#3" or "sh3d/chair_1"
  std::string cls;        // object class: "chair", "table", ...
  std::string source;     // "procedural" or "sweethome3d"
  TriMesh mesh;
  Eigen::Vector2f half_extent = Eigen::Vector2f::Zero();  // footprint half sizes (x, y)
  float height = 0.0f;
  float reflectivity = 0.5f;  // Lambertian reflectivity used for intensity
  float size() const { return 2.0f * half_extent.maxCoeff(); }
};

// Indoor classes of the procedural library.
const std::vector<std::string>& indoor_classes();
// Outdoor (training yard) classes.
const std::vector<std::string>& outdoor_classes();

// A procedural shape of class `cls`; `variant` picks the parameters (same
// variant, same geometry). Throws lista::Error for an unknown class.
Shape make_shape(const std::string& cls, uint64_t variant);

// Gives shapes of identical geometry one id, the first's: a few classes have
// discrete variants (pallet sizes, container lengths), and two variant
// numbers that build the same mesh are one shape, not two look-alikes that
// no descriptor could tell apart. Paint (reflectivity) is not geometry.
void share_ids_of_identical_geometry(std::vector<Shape>& shapes);

// A walking person (dynamic distractor).
Shape make_person(uint64_t variant);

// Recomputes half_extent and height from the mesh after re-centring it on its
// footprint (x, y centre at 0, lowest point at z = 0).
void normalise_shape(Shape& shape);

}  // namespace lista::sim
