#include "euclidean_clustering.hpp"

#include <lista_pcl/convert.hpp>
#include <lista_pcl/fast_kdtree.hpp>

#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>

#include <algorithm>

namespace lista::segment {

std::vector<std::vector<uint32_t>> cluster_euclidean(const PointSet& points,
                                                     const EuclideanClusterConfig& config) {
  if (points.empty()) return {};
  auto cloud = pcl_convert::to_xyz(points);
  auto tree = std::make_shared<pcl_search::FastKdTree>();
  tree->setInputCloud(cloud);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(config.tolerance);
  ec.setMinClusterSize(int(std::min<size_t>(config.min_points, INT32_MAX)));
  ec.setMaxClusterSize(int(std::min<size_t>(config.max_points, INT32_MAX)));
  ec.setSearchMethod(tree);
  ec.setInputCloud(cloud);
  std::vector<pcl::PointIndices> found;
  ec.extract(found);

  std::vector<std::vector<uint32_t>> clusters;
  for (const auto& c : found) {
    clusters.push_back(pcl_convert::to_indices(c.indices));
    std::sort(clusters.back().begin(), clusters.back().end());
  }
  // PCL orders by size; order by first index so output is stable and comparable.
  std::sort(clusters.begin(), clusters.end(),
            [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return clusters;
}

}  // namespace lista::segment
