// Internal: a stream of stamped poses (odometry, PoseStamped, a TUM file)
// looked up at a cloud's stamp.
#pragma once

#include <lista_bag/messages.hpp>

#include <optional>

namespace lista::bag {

// Sorts by stamp. The pose at `stamp`, interpolated between the two poses
// around it (translation linearly, rotation by slerp); nullopt outside the
// stream's time range: a cloud there is skipped, never extrapolated.
class Trajectory {
 public:
  explicit Trajectory(std::vector<StampedPose> poses);
  std::optional<Eigen::Isometry3d> at(double stamp) const;
  bool empty() const { return poses_.empty(); }
  double median_interval() const;  // s between consecutive poses; 0 for fewer than two

 private:
  std::vector<StampedPose> poses_;
};

// The median gap between sorted stamps; 0 for fewer than two.
double median_interval(std::vector<double> stamps);

}  // namespace lista::bag
