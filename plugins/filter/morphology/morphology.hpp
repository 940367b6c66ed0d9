// Morphological opening of the voxelised change: erosion, then dilation
// restricted to the voxels that were occupied. Returns the indices of the
// ORIGINAL points whose voxel survives.
//
// Structuring element: the 26-neighbourhood (3x3x3 cube). Pure erosion with
// that cube would erase any surface one voxel thick - i.e. every LiDAR
// surface - so erosion keeps a voxel when at least `min_neighbours` of its 26
// neighbours are occupied (a rank filter). Lone voxels (noise, 0-2
// neighbours), lines and strips at most two voxels wide (wall edges seen at
// grazing angles: <= 5 neighbours) go; the inside of any surface patch at
// least three voxels wide (>= 8 neighbours) stays, so a small object of
// 3x3x3 voxels survives. Dilation by the same cube then restores the
// object's border voxels that erosion removed, but never adds empty voxels.
// With `reconstruct` (default) dilation repeats until nothing changes: an
// opening by reconstruction, which gives back every voxel connected to a
// surviving core, so thin parts of real objects (legs, shelf boards, edges
// of flat tops: 1-2 voxels wide) stay with their object; what has no core at
// all (noise, slivers standing alone) still goes.
#pragma once

#include <lista/points.hpp>

#include <cstdint>
#include <vector>

namespace lista::filter {

struct MorphologyConfig {
  double voxel = 0.1;       // m
  int min_neighbours = 6;   // erosion: occupied 26-neighbours needed to survive
  int dilate_steps = 1;     // dilation repeats (each by the 3x3x3 cube), without reconstruct
  bool reconstruct = true;  // dilate until stable: keep whole components that have a core
};

std::vector<uint32_t> morphology_keep(const PointSet& points, const MorphologyConfig& config);

}  // namespace lista::filter
