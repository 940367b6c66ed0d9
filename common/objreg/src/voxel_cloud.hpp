// An object's points as a PCL cloud, downsampled to one point per voxel
// (lista_objreg's registration and fit measures share it).
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>
#include <vector>

namespace lista::objreg {

// `pts` averaged per `voxel` (0 = all points as they are); the points
// themselves when fewer than 3 voxels remain (too few to register).
pcl::PointCloud<pcl::PointXYZ>::Ptr voxel_cloud(const std::vector<Eigen::Vector3f>& pts, double voxel);

}  // namespace lista::objreg
