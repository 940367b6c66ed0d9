#include <lista_alignkit/cloud_ops.hpp>

#include <lista/error.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace lista::alignkit {

Cloud voxel_downsample(const Cloud& points, double voxel) {
  if (voxel <= 0.0) throw Error("voxel size must be > 0");
  struct Acc {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    int n = 0;
  };
  // 21 bits per axis: +-1M voxels, far beyond any map at >= 1 cm.
  auto key = [voxel](const Eigen::Vector3f& p) {
    const auto q = [voxel](float v) {
      return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v / voxel)) + (1 << 20)) & 0x1FFFFF;
    };
    return (q(p.x()) << 42) | (q(p.y()) << 21) | q(p.z());
  };
  std::unordered_map<uint64_t, Acc> cells;
  cells.reserve(points.size() / 4 + 1);
  for (const auto& p : points) {
    Acc& a = cells[key(p)];
    a.sum += p.cast<double>();
    ++a.n;
  }
  std::vector<std::pair<uint64_t, Eigen::Vector3f>> out;
  out.reserve(cells.size());
  for (const auto& [k, a] : cells) out.emplace_back(k, (a.sum / a.n).cast<float>());
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  Cloud result;
  result.reserve(out.size());
  for (const auto& o : out) result.push_back(o.second);
  return result;
}

Cloud voxel_downsample_at_most(const Cloud& points, double voxel, size_t max_points) {
  Cloud out = voxel_downsample(points, voxel);
  while (out.size() > max_points) {
    voxel *= 1.25;
    out = voxel_downsample(points, voxel);
  }
  return out;
}

Cloud within_range(const Cloud& points, double range) {
  const float r2 = static_cast<float>(range * range);
  Cloud near;
  for (const auto& p : points)
    if (p.squaredNorm() <= r2) near.push_back(p);
  return near;
}

Eigen::Isometry3d levelled_frame(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d x = pose.linear().col(0);
  // Heading from the sensor's x axis projected on the ground plane; a sensor
  // looking straight up or down falls back to its y axis.
  double yaw = std::atan2(x.y(), x.x());
  if (std::hypot(x.x(), x.y()) < 1e-3) {
    const Eigen::Vector3d y = pose.linear().col(1);
    yaw = std::atan2(y.y(), y.x()) - M_PI / 2;
  }
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  frame.translation() = pose.translation();
  return frame;
}

double rotation_angle(const Eigen::Matrix3d& rotation) {
  return Eigen::AngleAxisd(Eigen::Quaterniond(rotation).normalized()).angle();
}

}  // namespace lista::alignkit
