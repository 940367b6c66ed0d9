#include "mls_smoothing.hpp"

#include <lista/error.hpp>
#include <lista_pcl/convert.hpp>
#include <lista_pcl/fast_kdtree.hpp>

#include <pcl/search/kdtree.h>
#include <pcl/surface/mls.h>

#include <cmath>

namespace lista::filter {

PointSet mls_smooth(const PointSet& points, const MlsConfig& c, int threads, size_t* fitted) {
  if (!(c.radius > 0)) throw Error("MLS radius must be > 0");
  if (fitted) *fitted = 0;
  if (points.empty()) return points;
  auto cloud = pcl_convert::to_xyz(points);
  pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointXYZ> mls;
  mls.setInputCloud(cloud);
  mls.setSearchMethod(std::make_shared<pcl_search::FastKdTree>());
  mls.setSearchRadius(c.radius);
  mls.setPolynomialOrder(c.polynomial_order);
  mls.setComputeNormals(false);
  mls.setUpsamplingMethod(pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointXYZ>::NONE);
  mls.setNumberOfThreads(unsigned(std::max(1, threads)));
  pcl::PointCloud<pcl::PointXYZ> smoothed;
  mls.process(smoothed);
  // With no upsampling, output k came from input corresponding[k].
  const auto corresponding = mls.getCorrespondingIndices();
  if (!corresponding || corresponding->indices.size() != smoothed.size())
    throw Error("MLS returned no point correspondences");

  std::vector<char> moved(points.size(), 0);
  PointSet out = points;
  for (size_t k = 0; k < smoothed.size(); ++k) {
    const auto i = size_t(corresponding->indices[k]);
    const auto& p = smoothed[k];
    if (i >= points.size() || !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    out.xyz[i] = Eigen::Vector3f(p.x, p.y, p.z);
    moved[i] = 1;
  }
  size_t n = 0;
  for (char m : moved) n += size_t(m);
  if (fitted) *fitted = n;
  if (!c.drop_unfitted) return out;
  std::vector<uint32_t> keep;
  for (uint32_t i = 0; i < points.size(); ++i)
    if (moved[i]) keep.push_back(i);
  return out.select(keep);
}

}  // namespace lista::filter
