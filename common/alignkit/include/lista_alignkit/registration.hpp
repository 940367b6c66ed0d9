// Pairwise registration of two local clouds with PCL's Generalized ICP,
// coarse to fine, and an honest fitness (overlap and inlier RMSE measured
// after the fact with a k-d tree), so that a wrong loop closure can be refused.
#pragma once

#include <lista_alignkit/cloud_ops.hpp>

#include <Eigen/Geometry>
#include <memory>
#include <string>

namespace lista::align {

struct RegistrationOptions {
  // "gicp": PCL's Generalized ICP (BFGS); "gicp_gn": ours, the GICP cost
  // solved by Gauss-Newton, with covariances that give a one-ring strip no
  // plane (about as fast per pair; many times nearer the truth on a sparse
  // scanner's scan pairs; opt-in: end to end its reports moved both ways,
  // docs/bench/alignment.md); "icp": PCL's point-to-point ICP.
  std::string method = "gicp";
  double voxel = 0.2;           // m; fine-stage downsampling
  double coarse_distance = 2.0; // m; max correspondence distance of the coarse stage
  double fine_distance = 0.5;   // m; of the fine stage
  int max_iterations = 40;      // per stage
  double inlier_distance = 0.3; // m; for the fitness measure
  // Early refusal: after the coarse stage, the share of coarse source points
  // with a coarse target point within the coarse voxel edge, both ways; below
  // this the fine stage is skipped and the result is not converged (0: off).
  double min_coarse_overlap = 0.0;
};

struct RegistrationResult {
  bool converged = false;
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // source -> target
  double overlap = 0.0;         // share of source points with a target point within inlier_distance
  double reverse_overlap = 0.0; // share of target points with a source point within inlier_distance
  double inlier_rmse = 0.0;     // m, over the source inliers
};

// Whether a registration measured a relative pose (align.posegraph's
// scan-to-scan edges): converged, the source's overlap (with `both_ways`
// the smaller of the two) at least min_overlap, inlier RMSE at most
// max_rmse, and no farther from the guess than a correction goes (farther
// is a wrong minimum).
struct RegistrationGates {
  double min_overlap = 0.5;
  double max_rmse = 0.15;               // m
  double max_translation_change = 0.5;  // m
  double max_rotation_change = 0.087;   // rad
  bool accept(const RegistrationResult& r, const Eigen::Isometry3d& guess, bool both_ways) const;
};

// A cloud made ready once for any number of registrations: its coarse and
// fine PCL clouds with their k-d trees and (for GICP) per-point covariances.
// A scan or submap registered against several others is prepared once
// (align.posegraph: 18.8 -> 11.4 s on exp1, where each scan and keyframe
// submap is registered several times). Immutable after construction, so one
// prepared cloud may serve many threads at once.
class PreparedCloud {
 public:
  PreparedCloud() = default;
  // `points` expected already downsampled to about options.voxel.
  PreparedCloud(const Cloud& points, const RegistrationOptions& options);
  size_t size() const;
  struct Impl;

 private:
  friend RegistrationResult register_prepared(const PreparedCloud&, const PreparedCloud&, const Eigen::Isometry3d&,
                                              const RegistrationOptions&);
  std::shared_ptr<const Impl> impl_;
};

// Aligns `source` onto `target` starting from `guess` (source -> target).
// Both prepared with the same options.
RegistrationResult register_prepared(const PreparedCloud& source, const PreparedCloud& target,
                                     const Eigen::Isometry3d& guess, const RegistrationOptions& options);

// The same for clouds registered once (prepares both).
RegistrationResult register_clouds(const Cloud& source, const Cloud& target,
                                   const Eigen::Isometry3d& guess, const RegistrationOptions& options);

}  // namespace lista::align
