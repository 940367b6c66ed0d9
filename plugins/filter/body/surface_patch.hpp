// The surface a scan shows in one sensor-frame cell: centre and normal,
// where its points there are flat enough to have one. Internal to
// filter.body.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <utility>
#include <vector>

namespace lista::filter {

// A patch of surface: centre and normal of a scan's points in a cell and
// its neighbours; `valid` only where they are flat enough to have a normal.
struct Patch {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero(), normal = Eigen::Vector3d::UnitZ();
  bool valid = false;
};

// The patch of cell `key` (geometry::voxel_key) from a scan's points keyed
// by cell and sorted by key: the points of the cell and its 26 neighbours.
Patch patch_of(const std::vector<std::pair<uint64_t, Eigen::Vector3f>>& keyed, uint64_t key);

}  // namespace lista::filter
