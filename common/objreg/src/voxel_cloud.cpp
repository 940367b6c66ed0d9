#include "voxel_cloud.hpp"

#include <pcl/filters/voxel_grid.h>

namespace lista::objreg {

pcl::PointCloud<pcl::PointXYZ>::Ptr voxel_cloud(const std::vector<Eigen::Vector3f>& pts, double voxel) {
  using Cloud = pcl::PointCloud<pcl::PointXYZ>;
  Cloud::Ptr c(new Cloud);
  c->reserve(pts.size());
  for (const auto& p : pts) c->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  if (voxel <= 0.0) return c;
  Cloud::Ptr d(new Cloud);
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setLeafSize(float(voxel), float(voxel), float(voxel));
  grid.setInputCloud(c);
  grid.filter(*d);
  return d->size() >= 3 ? d : c;
}

}  // namespace lista::objreg
