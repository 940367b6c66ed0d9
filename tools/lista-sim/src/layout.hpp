// Static environments: open-plan offices, industrial halls and an outdoor
// yard, each with its structure (label 0), the free floor area objects may
// use, and a closed inspection route.
#pragma once

#include "footprint.hpp"
#include "mesh.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace lista::sim {

struct StructurePart {
  TriMesh mesh;  // world frame
  float reflectivity = 0.5f;
};

struct Layout {
  std::string kind;  // "office", "hall", "yard"
  std::vector<StructurePart> structure;
  std::vector<Footprint> obstacles;       // structure footprints objects must avoid
  Eigen::Vector2d area_min, area_max;      // free floor rectangle for objects
  std::vector<Eigen::Vector2d> route;      // closed loop (last point joins the first)
  double route_clearance = 0.8;            // objects keep this far from the route
  double sensor_height = 0.7;              // sensor above the floor
  double route_length() const;
  // Point at arclength s (wrapped) and the unit tangent there.
  Eigen::Vector2d route_point(double s, Eigen::Vector2d* tangent = nullptr) const;
  // The route as corridor footprints (half width = route_clearance).
  std::vector<Footprint> corridor() const;
};

struct LayoutParams {
  std::string kind = "office";
  double width = 12.0, length = 9.0, height = 2.8;  // x, y extent and ceiling height
};

// Throws lista::Error for an unknown kind or a space too small for a route.
Layout build_layout(const LayoutParams& params, uint64_t seed);

}  // namespace lista::sim
