// One source view registered onto one target from many starts: the evenly
// strided subsets ICP iterates on, PCL's ICP and GICP set up once for all
// starts, and the score of a pose. Internal to lista_objreg (icp_refine.cpp).
#pragma once

#include <lista_objreg/icp_refine.hpp>
#include <lista_pcl/fast_kdtree.hpp>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <memory>

namespace lista::objreg {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// A pose of the source and its score: the truncated mean squared distance
// both ways (IcpResult::score), and the share of each side within the
// inlier distance.
struct Candidate {
  Eigen::Isometry3d t;
  double score, in_source, in_target;
};

class PairIcp {
 public:
  // `src`, `dst`: the voxelised source and target clouds.
  PairIcp(const Cloud::Ptr& src, const Cloud::Ptr& dst, const IcpConfig& cfg);
  PairIcp(const PairIcp&) = delete;
  PairIcp& operator=(const PairIcp&) = delete;

  // ICP from `guess` with the correspondence gate `max_correspondence`:
  // GICP when configured and both clouds hold enough points for its
  // covariances, else (or when `point_to_point`) point-to-point. Returns
  // the guess when ICP does not converge.
  Eigen::Isometry3d refine(const Eigen::Isometry3d& guess, double max_correspondence, bool point_to_point = false);
  // `t` scored on the whole voxelised clouds.
  Candidate scored(const Eigen::Isometry3d& t) const;
  // Switches both registrations to the fine pass's larger subset, once.
  void use_fine_points();
  // The fine pass iterates on the same points as the coarse one.
  bool fine_is_coarse() const { return src_fine_ == src_icp_; }
  bool uses_gicp() const { return use_gicp_; }

 private:
  Cloud::Ptr strided(int max_points) const;

  const IcpConfig& cfg_;
  Cloud::Ptr src_, dst_, src_icp_, src_fine_;
  pcl_search::FastKdTree src_tree_, dst_tree_;
  bool gicp_method_ = false, use_gicp_ = false;
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp_;
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp_;
  // Their target trees answer correspondence queries only within the gate.
  std::shared_ptr<pcl_search::FastKdTree> gicp_target_, icp_target_;
};

}  // namespace lista::objreg
