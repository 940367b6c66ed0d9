// How far apart two aligned missions hold the surfaces they share: the
// alignment's misfit, measured where it shows (docs/volumetric.md,
// "Misfit"). A wall one mission holds two voxels from where the other holds
// it is change at every voxel between, though nothing moved.
#pragma once

#include <lista/missions.hpp>
#include <lista_raycast/change_detection.hpp>

namespace lista::raycast {

// The median distance, in voxels, from points of `mission` (about 8 000,
// evenly spread) to the local plane of the occupied voxels `other` holds
// within two voxels of them, along the plane's normal; walls and floors
// apart, the larger of the two medians (a shift along a floor shows on the
// walls only, a height error on the floors only). Points without a plane
// there (too few voxels, or not flat) are left out; 0 when fewer than 50 of
// either kind remain. Aligned missions measured 0.16-0.33 voxels (the
// voxels' own quantisation), a 5 cm shift 0.53, a 10 cm one about 1.
double surface_misfit(const Mission& mission, const OccupancyMap& other, const VolumetricConfig& config);

// The neighbourhood (voxels) a pair of missions is judged with: a changed
// voxel must have no voxel the other mission holds within it. The measured
// misfit (the larger way round) widens the configured one to twice it less
// half a voxel (what quantisation alone gives), rounded up, so that a wall
// the alignment left a little apart is not change: 2 voxels for a 10 cm
// shift at 5 cm voxels; a pair that fits stays at the configured one.
int pair_neighbourhood(double misfit, int neighbourhood);

}  // namespace lista::raycast
