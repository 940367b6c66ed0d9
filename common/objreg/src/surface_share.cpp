#include <lista_objreg/surface_share.hpp>

#include <lista_pcl/fast_kdtree.hpp>

#include "voxel_cloud.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace lista::objreg {

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// `q` between the sampled lines of a surface: within `tolerance` of the
// neighbours' plane and inside their spread in it. One ring (a line) has
// no spread across it, so a point beside it is never inside.
bool between_samples(const Eigen::Vector3f& q, const Cloud& cloud, const pcl::Indices& near, double tolerance) {
  if (near.size() < 4) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto i : near) mean += cloud[i].getVector3fMap().cast<double>();
  mean /= double(near.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto i : near) {
    const Eigen::Vector3d d = cloud[i].getVector3fMap().cast<double>() - mean;
    cov += d * d.transpose();
  }
  cov /= double(near.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Vector3d lambda = eig.eigenvalues();  // ascending
  const Eigen::Vector3d d = q.cast<double>() - mean;
  if (std::abs(eig.eigenvectors().col(0).dot(d)) > tolerance) return false;
  // Inside the spread (Mahalanobis radius 1.5 in the plane): between the
  // lines, not past the object's edge.
  const double a = eig.eigenvectors().col(1).dot(d), b = eig.eigenvectors().col(2).dot(d);
  if (lambda(1) <= 1e-12) return false;  // no spread to divide by
  return a * a / lambda(1) + b * b / lambda(2) <= 2.25;
}

// Share of `src` points, moved by `t`, on the surface of `dst` (searched by
// `tree`).
double one_way(const Cloud& src, const Cloud& dst, const pcl_search::FastKdTree& tree, const Eigen::Isometry3d& t,
               const SurfaceShareConfig& cfg) {
  const Eigen::Isometry3f tf = t.cast<float>();
  const double step = cfg.max_points > 0 && src.size() > size_t(cfg.max_points)
                          ? double(src.size()) / cfg.max_points : 1.0;
  const float inlier2 = float(cfg.inlier * cfg.inlier);
  // Nothing beyond the inlier distance or the gap counts: searched no farther.
  const float reach2 = std::max(inlier2, float(cfg.gap * cfg.gap));
  pcl::Indices near;
  std::vector<float> d2;
  size_t used = 0, on = 0;
  for (double k = 0.0; k < double(src.size()); k += step, ++used) {
    const Eigen::Vector3f q = tf * src[size_t(k)].getVector3fMap();
    const pcl::PointXYZ p(q.x(), q.y(), q.z());
    float nearest = 0.0f;
    const bool found = tree.nearest(p, nearest, reach2) >= 0;
    if (found && nearest < inlier2) {
      ++on;
      continue;
    }
    if (cfg.gap <= cfg.inlier || !found) continue;
    tree.radiusSearch(p, cfg.gap, near, d2, 64);
    if (between_samples(q, dst, near, 0.5 * cfg.inlier)) ++on;
  }
  return used == 0 ? 0.0 : double(on) / double(used);
}

}  // namespace

SurfaceShares surface_shares(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                             const Eigen::Isometry3d& t, const SurfaceShareConfig& cfg) {
  if (source.empty() || target.empty()) return {};
  // Each view downsampled and indexed once, for both directions.
  const Cloud::Ptr src = voxel_cloud(source, cfg.voxel);
  const Cloud::Ptr dst = voxel_cloud(target, cfg.voxel);
  pcl_search::FastKdTree src_tree, dst_tree;
  src_tree.setInputCloud(src);
  dst_tree.setInputCloud(dst);
  return {one_way(*src, *dst, dst_tree, t, cfg), one_way(*dst, *src, src_tree, t.inverse(), cfg)};
}

}  // namespace lista::objreg
