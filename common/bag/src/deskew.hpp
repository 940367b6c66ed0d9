// Internal: undoing the skew of a sweep taken while the sensor moved.
#pragma once

#include <lista/points.hpp>

#include <Eigen/Geometry>
#include <functional>
#include <optional>
#include <vector>

namespace lista::bag {

// Sensor pose at a time (s); nullopt outside the poses' time range.
using PoseAt = std::function<std::optional<Eigen::Isometry3d>(double stamp)>;

// Each point of a sweep is measured in the sensor frame of its own time
// (stamp + times[i]); brings it into the frame at `stamp`, with the motion
// between them interpolated from `pose_at` at a few knots across the sweep.
// False (points untouched) when the poses do not cover the sweep.
bool deskew(PointSet& points, const std::vector<double>& times, double stamp, const PoseAt& pose_at);

}  // namespace lista::bag
