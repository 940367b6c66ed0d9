#include "trajectory.hpp"

#include <lista_geometry/order_statistics.hpp>

#include <algorithm>

namespace lista::bag {

Trajectory::Trajectory(std::vector<StampedPose> poses) : poses_(std::move(poses)) {
  std::stable_sort(poses_.begin(), poses_.end(), [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; });
}

std::optional<Eigen::Isometry3d> Trajectory::at(double stamp) const {
  if (poses_.empty() || stamp < poses_.front().stamp || stamp > poses_.back().stamp) return std::nullopt;
  const auto after = std::lower_bound(poses_.begin(), poses_.end(), stamp,
                                      [](const StampedPose& p, double t) { return p.stamp < t; });
  if (after->stamp == stamp || after == poses_.begin()) return after->pose;
  const StampedPose& before = *(after - 1);
  const double a = (stamp - before.stamp) / (after->stamp - before.stamp);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Quaterniond q0(before.pose.linear()), q1(after->pose.linear());
  T.linear() = q0.slerp(a, q1).toRotationMatrix();
  T.translation() = (1.0 - a) * before.pose.translation() + a * after->pose.translation();
  return T;
}

double median_interval(std::vector<double> stamps) {
  if (stamps.size() < 2) return 0.0;
  std::sort(stamps.begin(), stamps.end());
  std::vector<double> gaps;
  for (size_t i = 1; i < stamps.size(); ++i) gaps.push_back(stamps[i] - stamps[i - 1]);
  return geometry::median(gaps);
}

double Trajectory::median_interval() const {
  std::vector<double> stamps;
  for (const auto& p : poses_) stamps.push_back(p.stamp);
  return lista::bag::median_interval(std::move(stamps));
}

}  // namespace lista::bag
