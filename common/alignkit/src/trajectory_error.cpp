#include <lista_alignkit/trajectory_error.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>

namespace lista::alignkit {

std::optional<TrajectoryError> trajectory_error(const MissionSet& set) {
  std::vector<Eigen::Vector3d> est, gt;
  for (const auto& m : set.missions) {
    if (m.poses_gt.size() != m.scans.size() || m.scans.empty()) return std::nullopt;
    for (size_t i = 0; i < m.scans.size(); ++i) {
      est.push_back(m.sensor_to_common(i).translation());
      gt.push_back(m.poses_gt[i].translation());
    }
  }
  if (est.size() < 3) return std::nullopt;
  Eigen::Matrix3Xd src(3, est.size()), dst(3, gt.size());
  for (size_t i = 0; i < est.size(); ++i) {
    src.col(i) = est[i];
    dst.col(i) = gt[i];
  }
  const Eigen::Matrix4d T = Eigen::umeyama(src, dst, false);
  TrajectoryError e;
  e.fit.matrix() = T;
  double sum = 0.0;
  for (size_t i = 0; i < est.size(); ++i) {
    const double d = (T.topLeftCorner<3, 3>() * src.col(i) + T.topRightCorner<3, 1>() - dst.col(i)).norm();
    sum += d * d;
    e.max = std::max(e.max, d);
  }
  e.poses = est.size();
  e.rmse = std::sqrt(sum / est.size());
  return e;
}

std::string failed_alignment_warning(const TrajectoryError& error) {
  if (!(error.rmse > kFailedAlignmentRmse)) return "";
  char rmse[32];
  std::snprintf(rmse, sizeof rmse, "%.2f", error.rmse);  // centimetres say enough against a 0.5 m bar
  return "the aligned poses are " + std::string(rmse) +
         " m (RMSE) from poses_gt.txt: the alignment has probably failed; changes found will be wrong";
}

}  // namespace lista::alignkit
