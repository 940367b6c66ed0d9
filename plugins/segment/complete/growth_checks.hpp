// What completion measures and adds on an object: the shape a growth gives
// it, whether two shapes agree, its base next to the floor, how much of a
// thin patch its own mission's surface continues, and the notes `-v` prints.
// Internal to segment.complete.
#pragma once

#include "local_cloud.hpp"

#include <lista/objects.hpp>

#include <string>

namespace lista::segment::completion {

// Appends the mission cloud's points `add` to an object. They carry no
// change channel (they are the mission's points, not change points); they
// are part of the same changed object, so they take its ChangedAgainst bits.
void add_points(Object& o, const PointSet& cloud, const std::vector<uint32_t>& add);

// Height above the floor and the footprint-rectangle sides
// (larger first) of an object grown by `extra` points of `cloud`.
Eigen::Vector3f shape_of(const PointSet& own, const std::vector<uint32_t>& extra, const PointSet& cloud,
                         float floor, float min_z);

// Two decimals: what the notes print of metres and shares.
std::string format_number(double v);

// "height x side x side m" of shape_of's result.
std::string shape_note(const Eigen::Vector3f& s);

// Leaked voxels per voxel grown into.
std::string leak_note(const Growth& g);

// Whether two shape_of results agree within shape_tolerance (relative) or
// shape_slack (metres), each allowance times `strictness`.
bool same_shape(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const CompletionConfig& c, double strictness = 1.0);

// The base of an object standing on the floor: points of `cloud` below its
// lowest detected part, down to the floor clearance, in the 5 cm columns its
// lowest 15 cm occupy (grown by one column). The volumetric difference cannot
// confirm change that close to the floor (the floor voxel is occupied in both
// missions), so this is where a detected object most often lacks points.
std::vector<uint32_t> base_points(const Object& o, const LocalCloud& cloud, const Floor& floor,
                                  const Owners& owned);

constexpr float kSurfaceNoise = 0.02f;  // m: a scanned flat surface's points lie within this of its height

// On how many of its four sides a thin object's own mission continues its
// surface: a side counts when at least half of its 0.1 m columns, in a
// strip `ring` wide along the object's box, hold a point of `own` within
// `tol` of the object's median height. A patch of a larger horizontal
// surface (a shelf's top, a table's) has three or four; a thing standing
// free at that height (a cart's deck) none; the sliver of a table top moved
// a little, one (the rest of the top).
int surface_sides(const Object& o, const LocalCloud& own, float ring, float tol);

}  // namespace lista::segment::completion
