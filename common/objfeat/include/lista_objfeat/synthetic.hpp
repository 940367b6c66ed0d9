// Synthetic object instances and partial scans of them, built in code: for
// unit tests and for prototyping without a dataset. Each shape is a random
// furniture-like assembly of boxes, cylinders and spheres standing on z = 0;
// a view samples its surface, keeps what faces one sensor position (back-face
// culling), optionally cuts a random occluded slab, and adds range noise.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <vector>

namespace lista::objfeat {

struct Primitive {
  enum Kind { box, cylinder, sphere } kind = box;
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  Eigen::Vector3f half = Eigen::Vector3f::Constant(0.5f);  // box half-extents; cylinder (r, r, h/2); sphere (r, r, r)
};

struct Shape {
  std::vector<Primitive> parts;
};

struct ViewConfig {
  float points_per_m2 = 1500.f;   // surface density before culling
  float noise = 0.005f;           // gaussian noise sigma (m)
  float occlusion = 0.3f;         // probability of cutting an occluded slab
  float min_range = 2.f, max_range = 8.f;
};

// A random shape; the same rng state gives the same shape.
Shape random_shape(std::mt19937_64& rng);

// A partial scan of `shape` placed at (yaw, xy offset), seen from a random
// sensor position around it. Never empty (falls back to the full surface).
std::vector<Eigen::Vector3f> render_view(const Shape& shape, float yaw, const Eigen::Vector2f& offset,
                                         std::mt19937_64& rng, const ViewConfig& config = {});

}  // namespace lista::objfeat
