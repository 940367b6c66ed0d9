// Absolute trajectory error against poses_gt.txt: the estimated sensor
// positions of ALL missions (common frame) are aligned to the true ones
// (world frame) by ONE rigid transform (Horn/Umeyama, no scale), then the RMSE
// of the position differences. One transform for all missions, so that a
// mission misplaced relative to the others counts in full.
#pragma once

#include <lista/missions.hpp>

#include <Eigen/Geometry>
#include <optional>
#include <string>

namespace lista::alignkit {

struct TrajectoryError {
  double rmse = 0.0;  // m
  double max = 0.0;   // m
  size_t poses = 0;
  Eigen::Isometry3d fit = Eigen::Isometry3d::Identity();  // common frame -> world, the rigid fit used
};

// Empty when any mission lacks poses_gt (or its count differs from its scans),
// or fewer than 3 poses in all. `missions[m].to_common * scans[i].pose` is the estimate.
std::optional<TrajectoryError> trajectory_error(const MissionSet& missions);

// poses_gt.txt is there to be believed: aligned poses this far from it
// (RMSE) mean the alignment failed, and every change found will be wrong.
constexpr double kFailedAlignmentRmse = 0.5;  // m

// The warning an align stage logs for `error` above kFailedAlignmentRmse, else "".
std::string failed_alignment_warning(const TrajectoryError& error);

}  // namespace lista::alignkit
