// Objects: clusters of change points, one per mission appearance.
#pragma once

#include <lista/points.hpp>

#include <limits>
#include <string>
#include <vector>

namespace lista {

struct Object {
  int id = -1;           // unique within an ObjectSet (and the report)
  uint32_t mission = 0;  // index into ObjectSet::missions
  PointSet points;       // common frame, with provenance
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  Eigen::Vector3f bbox_min = Eigen::Vector3f::Zero();
  Eigen::Vector3f bbox_max = Eigen::Vector3f::Zero();
  // Height (z, frame of `points`) of the floor the object stands on; NaN
  // until a stage measures it (segment.complete does). Descriptors measure
  // heights from it: a view that misses the object's bottom has its lowest
  // point on the object's flank, not on the floor.
  float floor_z = std::numeric_limits<float>::quiet_NaN();
  void update_geometry();  // recomputes centroid and bounds from points
};

// Something that moved during one mission (a person walking by): a cluster
// of change points most of which the mission's own scans also saw free at
// another time. Listed in the report apart from the changes, never matched.
struct Dynamic {
  uint32_t mission = 0;
  uint32_t points = 0;
  Eigen::Vector3f centroid = Eigen::Vector3f::Zero();
  Eigen::Vector3f bbox_min = Eigen::Vector3f::Zero();
  Eigen::Vector3f bbox_max = Eigen::Vector3f::Zero();
};

struct ObjectSet {
  std::vector<std::string> missions;
  std::vector<Object> objects;
  std::vector<Dynamic> dynamics;  // kept by every stage that passes objects on
  const Object* find(int id) const;
  // Renumbers ids 0..n-1 in order (after a stage adds or removes objects).
  void renumber();
};

}  // namespace lista
