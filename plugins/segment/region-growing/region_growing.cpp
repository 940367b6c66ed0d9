#include "region_growing.hpp"

#include <lista_pcl/convert.hpp>
#include <lista_pcl/fast_kdtree.hpp>

#include <pcl/features/normal_3d_omp.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/region_growing.h>

#include <algorithm>
#include <cmath>

namespace lista::segment {

std::vector<std::vector<uint32_t>> cluster_region_growing(const PointSet& points,
                                                          const RegionGrowingConfig& c, int threads) {
  if (points.size() < 3) return {};
  auto cloud = pcl_convert::to_xyz(points);
  auto tree = std::make_shared<pcl_search::FastKdTree>();
  tree->setInputCloud(cloud);

  pcl::PointCloud<pcl::Normal>::Ptr normals(new pcl::PointCloud<pcl::Normal>);
  pcl::NormalEstimationOMP<pcl::PointXYZ, pcl::Normal> ne(unsigned(std::max(1, threads)));
  ne.setInputCloud(cloud);
  ne.setSearchMethod(tree);
  ne.setKSearch(c.normal_neighbours);
  ne.compute(*normals);

  pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> rg;
  rg.setMinClusterSize(int(std::min<size_t>(c.min_points, INT32_MAX)));
  rg.setMaxClusterSize(int(std::min<size_t>(c.max_points, INT32_MAX)));
  rg.setSearchMethod(tree);
  rg.setNumberOfNeighbours(c.neighbours);
  rg.setInputCloud(cloud);
  rg.setInputNormals(normals);
  rg.setSmoothnessThreshold(float(c.smoothness_deg * M_PI / 180.0));
  rg.setCurvatureThreshold(float(c.curvature));
  std::vector<pcl::PointIndices> found;
  rg.extract(found);

  std::vector<std::vector<uint32_t>> clusters;
  for (const auto& f : found) {
    if (f.indices.empty()) continue;
    clusters.push_back(pcl_convert::to_indices(f.indices));
    std::sort(clusters.back().begin(), clusters.back().end());
  }
  std::sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) { return a.front() < b.front(); });
  return clusters;
}

}  // namespace lista::segment
