#include "deskew.hpp"

#include <algorithm>

namespace lista::bag {

bool deskew(PointSet& points, const std::vector<double>& times, double stamp, const PoseAt& pose_at) {
  if (times.empty() || times.size() != points.size()) return false;
  const auto [lo, hi] = std::minmax_element(times.begin(), times.end());
  const std::optional<Eigen::Isometry3d> at_stamp = pose_at(stamp);
  if (!at_stamp) return false;
  // Knots across the sweep: the motion between pose samples is smooth, and
  // one pose lookup per point would cost more than the sweep's conversion.
  constexpr int kKnots = 16;
  const double t0 = *lo, span = *hi - *lo;
  const Eigen::Isometry3d to_stamp = at_stamp->inverse();
  std::vector<Eigen::Quaterniond> rotation(kKnots + 1);
  std::vector<Eigen::Vector3d> translation(kKnots + 1);
  for (int k = 0; k <= kKnots; ++k) {
    const std::optional<Eigen::Isometry3d> T = pose_at(stamp + t0 + span * k / kKnots);
    if (!T) return false;
    const Eigen::Isometry3d relative = to_stamp * *T;  // the frame at that time, seen from the stamp's
    rotation[size_t(k)] = Eigen::Quaterniond(relative.linear());
    translation[size_t(k)] = relative.translation();
  }
  for (size_t i = 0; i < points.size(); ++i) {
    const double u = span > 0.0 ? (times[i] - t0) / span * kKnots : 0.0;
    const int k = std::clamp(int(u), 0, kKnots - 1);
    const double a = std::clamp(u - k, 0.0, 1.0);
    const Eigen::Quaterniond q = rotation[size_t(k)].slerp(a, rotation[size_t(k) + 1]);
    const Eigen::Vector3d t = (1.0 - a) * translation[size_t(k)] + a * translation[size_t(k) + 1];
    points.xyz[i] = (q * points.xyz[i].cast<double>() + t).cast<float>();
  }
  return true;
}

}  // namespace lista::bag
