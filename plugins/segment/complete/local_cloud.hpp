// Completion's view of one mission: its points near the objects, indexed by
// voxel, the local floor under a region, the breadth-first growth through
// them and whether other missions hold the same voxels. Internal to
// segment.complete (completion.cpp and its rules).
#pragma once

#include "completion.hpp"

#include <lista/data.hpp>
#include <lista_geometry/boxes.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <unordered_map>
#include <utility>
#include <vector>

namespace lista::segment::completion {

using geometry::voxel_key;

using geometry::Box;

inline uint64_t point_key(uint32_t scan, uint32_t index) { return (uint64_t(scan) << 32) | index; }

// Point key -> index of the object that holds the point, per mission.
using Owners = std::unordered_map<uint64_t, uint32_t>;

// One mission's points near its objects and pairs, with a voxel index.
struct LocalCloud {
  PointSet points;                                  // common frame
  std::vector<std::pair<uint64_t, uint32_t>> grid;  // (voxel key, point), sorted
  float inv_voxel = 10.f;

  Eigen::Vector3i voxel_of(const Eigen::Vector3f& p) const {
    return (p * inv_voxel).array().floor().cast<int>();
  }
  void index() {
    grid.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) grid[i] = {voxel_key(voxel_of(points.xyz[i])), uint32_t(i)};
    std::sort(grid.begin(), grid.end());
  }
  // Calls f(i) for each point inside `b`. Keys sort by x, then y, then z,
  // so the voxels of one (x, y) column of the box are one range of `grid`:
  // a box over a few columns is read column by column, a box over more
  // columns than a scan of every point would cost, point by point.
  template <class F>
  void for_each_in(const Box& b, F&& f) const {
    if (points.empty() || !(b.lo.array() <= b.hi.array()).all()) return;
    const Eigen::Vector3i lo = voxel_of(b.lo), hi = voxel_of(b.hi);
    constexpr double kSearchCost = 32.0;  // points scanned for the price of one column's binary search
    if (double(hi.x() - lo.x() + 1) * double(hi.y() - lo.y() + 1) * kSearchCost > double(points.size())) {
      for (size_t i = 0; i < points.size(); ++i)
        if (b.contains(points.xyz[i])) f(uint32_t(i));
      return;
    }
    for (int x = lo.x(); x <= hi.x(); ++x)
      for (int y = lo.y(); y <= hi.y(); ++y) {
        const uint64_t last = voxel_key(Eigen::Vector3i(x, y, hi.z()));
        auto it = std::lower_bound(grid.begin(), grid.end(),
                                   std::make_pair(voxel_key(Eigen::Vector3i(x, y, lo.z())), uint32_t(0)));
        for (; it != grid.end() && it->first <= last; ++it)
          if (b.contains(points.xyz[it->second])) f(it->second);
      }
  }
  // Points in voxel v: a range of `grid`.
  std::pair<size_t, size_t> in_voxel(const Eigen::Vector3i& v) const {
    const uint64_t k = voxel_key(v);
    auto lo = std::lower_bound(grid.begin(), grid.end(), std::make_pair(k, uint32_t(0)));
    auto hi = lo;
    while (hi != grid.end() && hi->first == k) ++hi;
    return {size_t(lo - grid.begin()), size_t(hi - grid.begin())};
  }
};

// Gathers the points of `mission` (common frame) that fall inside any of
// `regions`, in scan then file order whatever the thread count.
LocalCloud gather(const Mission& mission, const std::vector<Box>& regions, float voxel, int threads);

// The points of `cloud` (indexed, as gather returns it) inside any of
// `regions`, in the same order, with its index: what gather(regions) would
// have returned, without reading the mission again.
LocalCloud restrict_to(const LocalCloud& cloud, const std::vector<Box>& regions);

// The local floor under `region`: the `percentile` of the lowest z per 0.2 m
// cell gives a first guess f0 (robust to objects covering part of the cells);
// the floor is the median of the points within 6 cm above f0 and its noise
// their MAD. Points below floor + max(min_clearance, 4 sigma) count as floor.
struct Floor {
  float z = 0.f;          // floor height
  float clear_z = 0.f;    // lowest z an object point may have
};

bool local_floor(const LocalCloud& cloud, const Box& region, double percentile, double min_clearance, Floor& floor);

// Breadth-first growth of `seed` through occupied voxels of `cloud` inside
// `region`, over points above `min_z` that nobody owns. Returns the new points.
struct Growth {
  std::vector<uint32_t> added;  // new points, ascending
  size_t voxels = 0;            // voxels it added points from
  size_t leaks = 0;             // voxels it would have entered outside the region
  std::vector<uint32_t> touched;  // objects (indices) owning points the walk reached, ascending
  // A growth that wants out of its region is part of something bigger (a
  // wall, the desk the object touches): not one object.
  bool contained(double max_leak) const { return double(leaks) <= max_leak * double(std::max<size_t>(voxels, 1)); }
};

Growth grow(const PointSet& seed, const LocalCloud& cloud, const Box& region, float min_z, const Owners& owned);

// Whether every one of the `neighbours`' clouds holds a point in a voxel,
// above its own local floor under `floor_region`. Not valid when a neighbour
// has no points there: it saw nothing of the place and cannot say it is
// static.
struct HeldElsewhere {
  std::vector<std::pair<const LocalCloud*, float>> others;  // cloud, lowest z that counts
  bool valid = false;

  HeldElsewhere(const Box& floor_region, const std::vector<size_t>& neighbours, const std::vector<LocalCloud>& clouds,
                const CompletionConfig& c);
  bool everywhere(const Eigen::Vector3i& v) const {
    for (const auto& [other, min_z] : others) {
      const auto [b, e] = other->in_voxel(v);
      bool held = false;
      for (size_t k = b; k < e && !held; ++k) held = other->points.xyz[other->grid[k].second].z() >= min_z;
      if (!held) return false;
    }
    return true;
  }
};

// The points of `add` (in `cloud`) whose voxel is not occupied, above the
// local floor, in every one of the `neighbours`' clouds: the rest is there in
// the other missions too, so it did not change.
std::vector<uint32_t> not_static(const std::vector<uint32_t>& add, const LocalCloud& cloud, const Box& floor_region,
                                 const std::vector<size_t>& neighbours, const std::vector<LocalCloud>& clouds,
                                 const CompletionConfig& c);

}  // namespace lista::segment::completion
