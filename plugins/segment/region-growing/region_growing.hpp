// PCL region growing with normals on one point set: neighbours join a region
// while their normals differ by less than `smoothness_deg`; growth continues
// from points whose curvature is below `curvature`. Splits clusters that
// touch along a crease (an object resting on a floor or against a wall, two
// objects side by side with different surface orientation).
#pragma once

#include <lista/points.hpp>

#include <cstdint>
#include <vector>

namespace lista::segment {

struct RegionGrowingConfig {
  int normal_neighbours = 16;    // k for normal estimation
  int neighbours = 16;           // k for region growing
  double smoothness_deg = 30.0;  // largest normal change between neighbours
  double curvature = 0.05;       // growth continues only from flatter points (1 = no limit)
  size_t min_points = 20;
  size_t max_points = 5000000;
};

// Clusters as sorted point indices, ordered by their first index.
std::vector<std::vector<uint32_t>> cluster_region_growing(const PointSet& points,
                                                          const RegionGrowingConfig& config, int threads);

}  // namespace lista::segment
