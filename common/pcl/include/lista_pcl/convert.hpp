// Conversions between lista::PointSet and PCL clouds, provided once for every
// plugin. Kept out of include/lista/ so the SDK never pulls PCL headers.
// Uses PCL's standard point types so its precompiled instantiations are used.
#pragma once

#include <lista/points.hpp>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdint>
#include <vector>

namespace lista::pcl_convert {

// xyz only. O(n) copy; provenance stays in the PointSet (same order).
pcl::PointCloud<pcl::PointXYZ>::Ptr to_xyz(const PointSet& points);
// xyz + intensity (0 where the set has none).
pcl::PointCloud<pcl::PointXYZI>::Ptr to_xyzi(const PointSet& points);
// Subset by indices (into `points`).
pcl::PointCloud<pcl::PointXYZ>::Ptr to_xyz(const PointSet& points, const std::vector<uint32_t>& indices);

// PCL index lists (e.g. from clustering) to uint32 indices.
std::vector<uint32_t> to_indices(const pcl::Indices& indices);

}  // namespace lista::pcl_convert
