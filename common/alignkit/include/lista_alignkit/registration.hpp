// Pairwise registration of two local clouds with PCL's Generalized ICP,
// coarse to fine, and an honest fitness (overlap and inlier RMSE measured
// after the fact with a k-d tree), so that a wrong loop closure can be refused.
#pragma once

#include <lista_alignkit/cloud_ops.hpp>

#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace lista::alignkit {

// gicp: PCL's Generalized ICP (BFGS); gicp_gn: ours, the GICP cost solved
// by Gauss-Newton, with covariances that give a one-ring strip no plane
// (about as fast per pair; many times nearer the truth on a sparse scanner's
// scan pairs, docs/bench/alignment.md); icp: PCL's point-to-point ICP.
enum class RegistrationMethod { gicp, gicp_gn, icp };

// The names the align.* stages' `registration` parameter gives them.
inline std::vector<std::pair<std::string, RegistrationMethod>> registration_method_names() {
  return {{"gicp", RegistrationMethod::gicp}, {"gicp_gn", RegistrationMethod::gicp_gn}, {"icp", RegistrationMethod::icp}};
}

struct RegistrationOptions {
  RegistrationMethod method = RegistrationMethod::gicp;
  double voxel = 0.2;           // m; fine-stage downsampling
  double coarse_distance = 2.0; // m; max correspondence distance of the coarse stage
  double fine_distance = 0.5;   // m; of the fine stage
  int max_iterations = 40;      // per stage
  double inlier_distance = 0.3; // m; for the fitness measure
  // Early refusal: after the coarse stage, the share of coarse source points
  // with a coarse target point within the coarse voxel edge, both ways; below
  // this the fine stage is skipped and the result is not converged (0: off).
  double min_coarse_overlap = 0.0;
  // Measure RegistrationResult::plane_rmse (the scan-edge gates need it):
  // the target's local planes are fitted when it is prepared, a second
  // neighbour search per point unless the method is gicp_gn, whose
  // covariances come from the same planes.
  bool measure_planes = false;
};

struct RegistrationResult {
  bool converged = false;
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // source -> target
  double overlap = 0.0;         // share of source points with a target point within inlier_distance
  double reverse_overlap = 0.0; // share of target points with a source point within inlier_distance
  double inlier_rmse = 0.0;     // m, over the source inliers
  // m, over the source inliers whose nearest target point has a local plane
  // (strips and corners have none): their distances along its normal; NaN
  // when no inlier has one or options.measure_planes is off. Unlike
  // inlier_rmse it does not grow with the gaps between a sparse scanner's
  // rings, which lie between each other's when two scans align.
  double plane_rmse = std::numeric_limits<double>::quiet_NaN();
};

// Whether a registration measured a relative pose (align.posegraph's
// scan-to-scan edges): converged, the source's overlap (with `both_ways`
// the smaller of the two) at least min_overlap, its RMSE under the bars that
// are on (> 0), and no farther from the guess than a correction goes
// (farther is a wrong minimum). max_plane_rmse needs plane_rmse measured
// (RegistrationOptions::measure_planes); unmeasured, it refuses.
struct RegistrationGates {
  double min_overlap = 0.5;
  double max_rmse = 0.15;               // m, inlier_rmse (point to point); 0: off
  double max_plane_rmse = 0.0;          // m, plane_rmse; 0: off
  double max_translation_change = 0.5;  // m
  double max_rotation_change = 0.087;   // rad
  bool accept(const RegistrationResult& r, const Eigen::Isometry3d& guess, bool both_ways) const;
};

// The gates align.posegraph judges a method's scan pairs by: for gicp_gn
// the RMSE along planes (at most `max_plane_rmse`), for the others point to
// point (at most `max_rmse`). On VLP-16 scan pairs the point-to-point RMSE
// of gicp_gn's accurate registrations (0.13-0.16 m, the ring gaps) sits at
// the 0.15 m bar, while along planes they score 2-5 cm; PCL's GICP, whose
// pairs pulled ring onto ring score lower point to point, gave worse
// reports when judged along planes (docs/bench/alignment.md, 2026-11-30).
RegistrationGates scan_pair_gates(RegistrationMethod method, double min_overlap, double max_rmse,
                                  double max_plane_rmse);

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

}  // namespace lista::alignkit
