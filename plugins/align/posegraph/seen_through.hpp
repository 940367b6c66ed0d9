// What a scan's sensor saw through: its nearest return in each direction
// (1-degree bins). A point another scan puts well in front of that return
// stands where this sensor's beam passed freely, so one of the two scans is
// misplaced (or the point moved between them). Station layouts are judged
// by it (station_vote.hpp). Internal to align.posegraph.
#pragma once

#include "loop_closures.hpp"

#include <Eigen/Geometry>

#include <vector>

namespace lista::align {

class SeenThrough {
 public:
  // `points` in the sensor's frame (a keyframe's submap: its own scan when
  // the keyframe is a station).
  explicit SeenThrough(const Cloud& points);
  // Share of `points` (in their own frame) that `sensor_T_points` puts in
  // front of the nearest return around their direction (the 3 x 3 bins
  // about it) by more than max(0.5 m, 5 %), among those whose direction
  // holds a return at all; judged on at most kMaxPoints of them, evenly
  // spread.
  double share_in_front(const Cloud& points, const Eigen::Isometry3d& sensor_T_points) const;

  static constexpr size_t kMaxPoints = 4096;

 private:
  static constexpr int kColumns = 360, kRows = 180;
  std::vector<float> nearest_;  // m per bin, infinity where nothing returned
};

}  // namespace lista::align
