// What a mission holds around the changed objects: its points in boxes
// around them, hashed for radius queries, and the share of an object's
// points a mission shows again. Internal to history.static.
#pragma once

#include <lista/missions.hpp>
#include <lista/objects.hpp>
#include <lista_geometry/boxes.hpp>
#include <lista_geometry/radius_grid.hpp>

#include <Eigen/Core>

#include <vector>

namespace lista::history {

using geometry::Box;

// A mission's points near the changed objects (common frame), hashed.
struct Cloud {
  PointSet points;
  geometry::RadiusGrid grid;
  explicit Cloud(float r) : grid(r) {}
  void add(const PointSet& from, size_t i, const Eigen::Vector3f& p) {
    points.push_back_from(from, i);
    points.xyz.back() = p;
    grid.add(p, uint32_t(points.size() - 1));
  }
};

// At most about 2000 of an object's points, evenly spread over its list.
std::vector<Eigen::Vector3f> sample(const PointSet& p);

// The share of `probe` within the radius of a point of `cloud`.
double share_near(const std::vector<Eigen::Vector3f>& probe, const Cloud& cloud);

// The points of `cloud` that show `object` again: those within the radius
// of its points, then those connected to them (within the radius) inside
// its box grown by the radius; none below its lowest point (segmentation
// kept the floor, and its noise, below that). The growth takes no point
// that `absent` (the mission where the object was not at this place) also
// shows: a wall or floor the object touches is there without it, and
// growing into it took in structure (a shelf against a wall, three times
// its own points). The first points are exempt: near the object's own, they
// keep its foot, which lies within the radius of the floor.
PointSet take(const Object& object, const Cloud& cloud, float radius, const Cloud* absent);

}  // namespace lista::history
