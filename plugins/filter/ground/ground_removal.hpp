// Ground removal by per-tile RANSAC: the map is cut into square xy tiles and
// in each tile near-horizontal planes are fitted (PCL SACSegmentation,
// SACMODEL_PERPENDICULAR_PLANE about z). A plane is ground when little lies
// under it within its own footprint; only points near such a plane go.
// Per-tile planes follow ramps and multi-level floors; the "nothing under it"
// test keeps table tops and box tops, which have their own sides and legs
// underneath. A plane's inliers are judged per patch (footprint cells linked
// across one-cell gaps), and a ground patch must spread over at least
// `min_area` (convex hull): pallets, cart decks and shelf bottoms are flat
// with nothing under them in a change cloud too, but smaller than a floor.
#pragma once

#include <lista/points.hpp>

#include <cstdint>
#include <vector>

namespace lista::filter {

struct GroundConfig {
  double tile_size = 4.0;          // m, tile edge
  double distance = 0.05;          // m, inlier distance to the plane
  double max_slope_deg = 15.0;     // steepest plane taken as ground
  int planes_per_tile = 3;         // candidate planes tried per tile
  size_t min_points = 30;          // smallest plane (inliers) considered
  double footprint_cell = 0.25;    // m, grid cell of the "what is under it" test
  double max_below_fraction = 0.05;  // under-plane points / inliers allowed for ground
  double min_area = 2.0;           // m^2, smallest footprint hull taken as ground (0 = any)
  int max_iterations = 200;        // RANSAC iterations
};

// Indices of the ground points of `points`, sorted. `threads` tiles at once.
std::vector<uint32_t> find_ground(const PointSet& points, const GroundConfig& config, int threads);

}  // namespace lista::filter
