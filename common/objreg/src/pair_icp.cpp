#include "pair_icp.hpp"

#include <lista_pcl/quiet.hpp>

#include <algorithm>

namespace lista::objreg {
namespace {

// Truncated mean squared nearest-neighbour distance of T*from to `to`, over
// at most max_points evenly strided points of `from` (0 = all).
double one_way(const Cloud& from, const pcl_search::FastKdTree& to_tree, const Eigen::Isometry3d& t,
               double inlier, int max_points, double& inlier_share) {
  const double cap = inlier * inlier;
  double sum = 0.0;
  size_t inliers = 0, used = 0;
  const Eigen::Isometry3f tf = t.cast<float>();
  const double step = max_points > 0 && from.size() > static_cast<size_t>(max_points)
                          ? static_cast<double>(from.size()) / max_points : 1.0;
  for (double k = 0.0; k < static_cast<double>(from.size()); k += step, ++used) {
    const Eigen::Vector3f q = tf * from[static_cast<size_t>(k)].getVector3fMap();
    // Farther than the inlier distance counts as the cap: searched no farther.
    float d2 = 0.0f;
    const double d = to_tree.nearest(pcl::PointXYZ(q.x(), q.y(), q.z()), d2, static_cast<float>(cap)) < 0
                         ? cap : std::min<double>(d2, cap);
    if (d < cap) ++inliers;
    sum += d;
  }
  inlier_share = used == 0 ? 0.0 : static_cast<double>(inliers) / used;
  return used == 0 ? cap : sum / used;
}

}  // namespace

// ICP's cost is one target search per source point and iteration: the
// coarse pass over every hypothesis iterates on an evenly strided subset
// (max_points), the fine pass on the few best on a larger one
// (fine_max_points); scores search the whole voxelised clouds (querying at
// most max_score_points each way).
PairIcp::PairIcp(const Cloud::Ptr& src, const Cloud::Ptr& dst, const IcpConfig& cfg)
    : cfg_(cfg),
      src_(src),
      dst_(dst),
      gicp_target_(std::make_shared<pcl_search::FastKdTree>()),
      icp_target_(std::make_shared<pcl_search::FastKdTree>()) {
  // The fine pass never iterates on fewer points than the coarse one.
  int fine_points = cfg.fine_max_points < 0 ? cfg.max_points : cfg.fine_max_points;
  if (cfg.max_points <= 0) fine_points = 0;
  else if (fine_points > 0 && fine_points < cfg.max_points) fine_points = cfg.max_points;
  src_icp_ = strided(cfg.max_points);
  src_fine_ = fine_points == cfg.max_points ? src_icp_ : strided(fine_points);  // also when the source is small enough for both
  src_tree_.setInputCloud(src_);
  dst_tree_.setInputCloud(dst_);
  // GICP estimates local covariances from 20 neighbours: too few points,
  // plain ICP (decided per pass: the fine subset may be large enough).
  gicp_method_ = cfg.method == PairMethod::gicp && dst_->size() >= 30;
  use_gicp_ = gicp_method_ && src_icp_->size() >= 30;
  // One registration object for all hypotheses: GICP then computes the
  // points' covariances once, not once per hypothesis.
  if (gicp_method_) {
    gicp_.setSearchMethodSource(std::make_shared<pcl_search::FastKdTree>());
    gicp_.setSearchMethodTarget(gicp_target_);
    gicp_.setInputSource(src_icp_);
    gicp_.setInputTarget(dst_);
  }
  // Point-to-point ICP always: the method itself, or GICP's final polish.
  icp_.setSearchMethodSource(std::make_shared<pcl_search::FastKdTree>());
  icp_.setSearchMethodTarget(icp_target_);
  icp_.setInputSource(src_icp_);
  icp_.setInputTarget(dst_);
}

Cloud::Ptr PairIcp::strided(int max_points) const {
  if (max_points <= 0 || src_->size() <= static_cast<size_t>(max_points)) return src_;
  Cloud::Ptr sub(new Cloud);
  const double step = static_cast<double>(src_->size()) / max_points;
  for (int k = 0; k < max_points; ++k) sub->push_back((*src_)[static_cast<size_t>(k * step)]);
  return sub;
}

// GICP then computes the larger subset's covariances once, not per hypothesis.
void PairIcp::use_fine_points() {
  if (fine_is_coarse()) return;
  use_gicp_ = gicp_method_ && src_fine_->size() >= 30;
  if (use_gicp_) gicp_.setInputSource(src_fine_);
  icp_.setInputSource(src_fine_);
}

Eigen::Isometry3d PairIcp::refine(const Eigen::Isometry3d& guess, double max_correspondence, bool point_to_point) {
  Cloud aligned;
  Eigen::Isometry3d t = guess;
  auto run = [&](auto& reg) {
    reg.setMaxCorrespondenceDistance(max_correspondence);
    const float gate = static_cast<float>(max_correspondence * max_correspondence);
    gicp_target_->set_nearest_bound(gate);
    icp_target_->set_nearest_bound(gate);
    reg.setMaximumIterations(cfg_.max_iterations);
    reg.setTransformationEpsilon(1e-8);
    {
      pcl_convert::QuietPcl quiet;  // "not enough correspondences" is judged below, not printed
      reg.align(aligned, guess.matrix().cast<float>());
    }
    if (reg.hasConverged()) {
      Eigen::Matrix4d m = reg.getFinalTransformation().template cast<double>();
      // Re-orthonormalise: float accumulation drifts slightly from SO(3).
      Eigen::Quaterniond q(Eigen::Matrix3d(m.topLeftCorner<3, 3>()));
      t = Eigen::Isometry3d::Identity();
      t.linear() = q.normalized().toRotationMatrix();
      t.translation() = m.topRightCorner<3, 1>();
    }
  };
  if (use_gicp_ && !point_to_point) run(gicp_);
  else run(icp_);
  return t;
}

Candidate PairIcp::scored(const Eigen::Isometry3d& t) const {
  Candidate c{t, 0.0, 0.0, 0.0};
  c.score = 0.5 * (one_way(*src_, dst_tree_, t, cfg_.inlier_distance, cfg_.max_score_points, c.in_source) +
                   one_way(*dst_, src_tree_, t.inverse(), cfg_.inlier_distance, cfg_.max_score_points, c.in_target));
  return c;
}

}  // namespace lista::objreg
