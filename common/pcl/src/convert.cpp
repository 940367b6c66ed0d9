#include <lista_pcl/convert.hpp>

namespace lista::pcl_convert {

pcl::PointCloud<pcl::PointXYZ>::Ptr to_xyz(const PointSet& points) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) (*cloud)[i].getVector3fMap() = points.xyz[i];
  cloud->width = static_cast<uint32_t>(points.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

pcl::PointCloud<pcl::PointXYZI>::Ptr to_xyzi(const PointSet& points) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZI>>();
  cloud->resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    (*cloud)[i].getVector3fMap() = points.xyz[i];
    (*cloud)[i].intensity = points.has_intensity() ? points.intensity[i] : 0.0f;
  }
  cloud->width = static_cast<uint32_t>(points.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

pcl::PointCloud<pcl::PointXYZ>::Ptr to_xyz(const PointSet& points, const std::vector<uint32_t>& indices) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->resize(indices.size());
  for (size_t i = 0; i < indices.size(); ++i) (*cloud)[i].getVector3fMap() = points.xyz[indices[i]];
  cloud->width = static_cast<uint32_t>(indices.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

std::vector<uint32_t> to_indices(const pcl::Indices& indices) {
  return std::vector<uint32_t>(indices.begin(), indices.end());
}

}  // namespace lista::pcl_convert
