// Absolute trajectory error against poses_gt.txt: the estimated sensor
// positions of ALL missions (common frame) are aligned to the true ones
// (world frame) by ONE rigid transform (Horn/Umeyama, no scale), then the RMSE
// of the position differences. One transform for all missions, so that a
// mission misplaced relative to the others counts in full.
#pragma once

#include <lista/missions.hpp>

#include <Eigen/Geometry>
#include <optional>

namespace lista::align {

struct TrajectoryError {
  double rmse = 0.0;  // m
  double max = 0.0;   // m
  size_t poses = 0;
  Eigen::Isometry3d fit = Eigen::Isometry3d::Identity();  // common frame -> world, the rigid fit used
};

// Empty when any mission lacks poses_gt (or its count differs from its scans),
// or fewer than 3 poses in all. `missions[m].to_common * scans[i].pose` is the estimate.
std::optional<TrajectoryError> trajectory_error(const MissionSet& missions);

}  // namespace lista::align
