// Small point-cloud helpers on plain Eigen vectors (no PCL): voxel centroids,
// the levelled local frame that descriptors and submaps are built in, and the
// angle of a rotation (for gates on how far two poses turn apart).
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace lista::alignkit {

using Cloud = std::vector<Eigen::Vector3f>;

// One centroid per occupied voxel of edge `voxel`, ordered by voxel key.
Cloud voxel_downsample(const Cloud& points, double voxel);

// voxel_downsample at `voxel`, coarser in x1.25 steps until at most
// `max_points` are left: registration time grows with points, accuracy
// hardly.
Cloud voxel_downsample_at_most(const Cloud& points, double voxel, size_t max_points);

// The points within `range` of the origin (of a sensor-frame scan: the
// sensor), in order.
Cloud within_range(const Cloud& points, double range);

// The pose with roll and pitch removed: same origin, z up, same heading.
// Descriptors are built in it so that yaw is the only rotation left to search.
Eigen::Isometry3d levelled_frame(const Eigen::Isometry3d& pose);

// Angle of a rotation matrix, in [0, pi] rad.
double rotation_angle(const Eigen::Matrix3d& rotation);

}  // namespace lista::alignkit
