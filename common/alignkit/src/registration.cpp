#include <lista_alignkit/registration.hpp>

#include <lista/error.hpp>
#include <lista_pcl/fast_kdtree.hpp>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <algorithm>
#include <cmath>

namespace lista::align {

namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;

PclCloud::Ptr to_pcl(const Cloud& cloud) {
  auto out = std::make_shared<PclCloud>();
  out->resize(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) out->points[i].getVector3fMap() = cloud[i];
  return out;
}

Eigen::Isometry3d run_stage(const PclCloud::Ptr& source, const PclCloud::Ptr& target,
                            const Eigen::Isometry3d& guess, double max_distance,
                            const RegistrationOptions& o, bool& converged) {
  std::unique_ptr<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> reg;
  if (o.method == "gicp") {
    auto g = std::make_unique<pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>>();
    g->setCorrespondenceRandomness(10);
    g->setRotationEpsilon(2e-4);  // rotation-matrix entries; 2e-4 is 4 mm at 20 m
    reg = std::move(g);
  } else {
    reg = std::make_unique<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>>();
  }
  // Single-query-fast trees (see fast_kdtree.hpp): GICP searches point by point.
  reg->setSearchMethodSource(std::make_shared<pcl_search::FastKdTree>());
  reg->setSearchMethodTarget(std::make_shared<pcl_search::FastKdTree>());
  reg->setInputSource(source);
  reg->setInputTarget(target);
  reg->setMaxCorrespondenceDistance(max_distance);
  reg->setMaximumIterations(o.max_iterations);
  // Stop when a step moves less than 0.1 mm. PCL's GICP compares the plain
  // translation step with the epsilon, its ICP the squared one.
  reg->setTransformationEpsilon(o.method == "gicp" ? 1e-4 : 1e-8);
  reg->setEuclideanFitnessEpsilon(1e-8);
  PclCloud aligned;
  reg->align(aligned, guess.matrix().cast<float>());
  converged = reg->hasConverged();
  Eigen::Isometry3d result(reg->getFinalTransformation().cast<double>());
  // Re-orthonormalise: float accumulation leaves a slightly skewed rotation.
  result.linear() = Eigen::Quaterniond(result.linear()).normalized().toRotationMatrix();
  return result;
}

// Share of `source` points (moved by t) with a `target` point within max_distance.
double overlap(const PclCloud& source, const PclCloud& target, const Eigen::Isometry3d& t, double max_distance) {
  auto tgt = std::make_shared<PclCloud>(target);
  pcl_search::FastKdTree tree;
  tree.setInputCloud(tgt);
  const Eigen::Isometry3f tf = t.cast<float>();
  size_t hits = 0;
  for (const auto& p : source.points) {
    pcl::PointXYZ q;
    q.getVector3fMap() = tf * p.getVector3fMap();
    const float d2 = tree.nearest_sqr_distance(q);
    if (d2 >= 0.0f && d2 <= max_distance * max_distance) ++hits;
  }
  return source.empty() ? 0.0 : static_cast<double>(hits) / source.size();
}

}  // namespace

RegistrationResult register_clouds(const Cloud& source, const Cloud& target,
                                   const Eigen::Isometry3d& guess, const RegistrationOptions& o) {
  if (o.method != "gicp" && o.method != "icp")
    throw Error("registration method must be 'gicp' or 'icp', got '" + o.method + "'");
  RegistrationResult result;
  if (source.size() < 20 || target.size() < 20) return result;

  // Coarse stage on a sparser cloud reaches further; fine stage settles it.
  const double coarse_voxel = std::max(o.voxel, o.coarse_distance / 4.0);
  auto src_coarse = to_pcl(voxel_downsample(source, coarse_voxel));
  auto tgt_coarse = to_pcl(voxel_downsample(target, coarse_voxel));
  bool converged = false;
  Eigen::Isometry3d t = guess;
  if (src_coarse->size() >= 20 && tgt_coarse->size() >= 20) {
    t = run_stage(src_coarse, tgt_coarse, guess, o.coarse_distance, o, converged);
    // Most wrong candidates show here, at a fraction of the fine stage's cost.
    if (o.min_coarse_overlap > 0.0) {
      const double d = std::max(coarse_voxel, o.inlier_distance);
      const double ov = std::min(overlap(*src_coarse, *tgt_coarse, t, d), overlap(*tgt_coarse, *src_coarse, t.inverse(), d));
      if (ov < o.min_coarse_overlap) {
        result.transform = t;
        result.overlap = result.reverse_overlap = ov;
        return result;
      }
    }
  }
  auto src = to_pcl(source);
  auto tgt = to_pcl(target);
  t = run_stage(src, tgt, t, o.fine_distance, o, converged);
  result.converged = converged;
  result.transform = t;

  pcl_search::FastKdTree tree;
  tree.setInputCloud(tgt);
  size_t inliers = 0;
  double sum_sq = 0.0;
  const double max_sq = o.inlier_distance * o.inlier_distance;
  const Eigen::Isometry3f tf = t.cast<float>();
  auto moved = to_pcl(source);
  for (auto& q : moved->points) {
    q.getVector3fMap() = tf * q.getVector3fMap();
    const float d2 = tree.nearest_sqr_distance(q);
    if (d2 >= 0.0f && d2 <= max_sq) {
      ++inliers;
      sum_sq += d2;
    }
  }
  result.overlap = static_cast<double>(inliers) / source.size();
  result.inlier_rmse = inliers ? std::sqrt(sum_sq / inliers) : 0.0;

  pcl_search::FastKdTree moved_tree;
  moved_tree.setInputCloud(moved);
  size_t reverse = 0;
  for (const auto& q : tgt->points) {
    const float d2 = moved_tree.nearest_sqr_distance(q);
    if (d2 >= 0.0f && d2 <= max_sq) ++reverse;
  }
  result.reverse_overlap = static_cast<double>(reverse) / target.size();
  return result;
}

}  // namespace lista::align
