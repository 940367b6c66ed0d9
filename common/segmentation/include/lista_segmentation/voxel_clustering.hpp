// Connected components of a point cloud on a voxel grid, by union-find.
// Two modes:
//  - voxel: occupied voxels of edge `tolerance` joined when 26-adjacent. Every
//    pair of points closer than `tolerance` ends up in one cluster, and no
//    cluster joins points whose gap exceeds 2*sqrt(3)*tolerance. Fastest.
//  - exact: the grid only limits the neighbour search; points are joined when
//    within `tolerance`. Same clusters as Euclidean cluster extraction (PCL)
//    at that tolerance.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace lista::segmentation {

struct VoxelClusterConfig {
  double tolerance = 0.1;        // voxel edge and joining distance, m
  bool exact = false;            // exact point distances instead of voxel adjacency
  size_t min_points = 20;        // smaller clusters are dropped
  size_t max_points = 5000000;   // larger clusters are dropped
};

// Clusters as sorted point indices, ordered by their first index.
std::vector<std::vector<uint32_t>> cluster_voxels(const std::vector<Eigen::Vector3f>& xyz,
                                                  const VoxelClusterConfig& config);

}  // namespace lista::segmentation
