// How far apart two aligned missions hold the surfaces they share: the
// alignment's misfit, measured where it shows (docs/volumetric.md,
// "Misfit"). A wall one mission holds two voxels from where the other holds
// it is change at every voxel between, though nothing moved.
#pragma once

#include <lista/missions.hpp>
#include <lista_raycast/change_detection.hpp>

#include <map>
#include <utility>

namespace lista::raycast {

// A square of the plan view (x, y in its units): a map bent by a SLAM
// drift, or one badly registered stretch of a mission, is off in some
// regions and fits in the rest, which the overall median does not show.
using Region = std::pair<int, int>;
Region region_of(const Eigen::Vector3d& voxel_point, const VolumetricConfig& config, double size);  // size in m

// The side of a pair's regions: 2 m, doubled until the two missions' points
// (every 16th) lie in at most 256 of them, so that the misfit's cost does
// not grow with a site's area (a 100 m yard: 8 m squares).
double region_size(const Mission& a, const Mission& b, const VolumetricConfig& config);

// How far apart `mission`'s points (about 8 000, evenly spread) and the
// surfaces `other` holds are, in voxels: each point's distance to the
// local plane of the occupied voxels `other` holds within two voxels of
// it, along the plane's normal; walls and floors apart, the larger of the
// two medians (a shift along a floor shows on the walls only, a height
// error on the floors only). Points without a plane there (too few voxels,
// or not flat) are left out. `overall`: 0 when fewer than 50 of either
// kind remain; aligned missions measured 0.16-0.33 voxels (the voxels' own
// quantisation), a 5 cm shift 0.53, a 10 cm one about 1. `regions`: the
// same per region, for those with 30 walls or floors measured; a region's
// points are measured evenly too (about 256 of every 16th point), so that
// a region the mission saw little of still counts.
struct SurfaceMisfit {
  double overall = 0.0;
  std::map<Region, double> regions;
};
// `region_size`: the side of `regions`' squares (region_size()).
SurfaceMisfit surface_misfit(const Mission& mission, const OccupancyMap& other, const VolumetricConfig& config,
                             double region_size);

// The neighbourhood (voxels) a pair of missions is judged with: a changed
// voxel must have no voxel the other mission holds within it. The measured
// misfit (the larger way round) widens the configured one to twice it less
// half a voxel (what quantisation alone gives), rounded up, so that a wall
// the alignment left a little apart is not change: 2 voxels for a 10 cm
// shift at 5 cm voxels; a pair that fits stays at the configured one.
int pair_neighbourhood(double misfit, int neighbourhood);

}  // namespace lista::raycast
