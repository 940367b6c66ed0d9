// PCL Euclidean cluster extraction on one point set.
#pragma once

#include <lista/points.hpp>

#include <cstdint>
#include <vector>

namespace lista::segment {

struct EuclideanClusterConfig {
  double tolerance = 0.1;  // joining distance, m
  size_t min_points = 20;
  size_t max_points = 5000000;
};

// Clusters as sorted point indices, ordered by their first index.
std::vector<std::vector<uint32_t>> cluster_euclidean(const PointSet& points,
                                                     const EuclideanClusterConfig& config);

}  // namespace lista::segment
