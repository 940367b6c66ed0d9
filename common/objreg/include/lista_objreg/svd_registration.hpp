// The paper's object registration: the matched objects share their centroid
// and their orientation is recovered from the SVD of each point covariance.
//
// Each object gets a principal frame: origin at the centroid, axes the
// covariance's singular vectors by decreasing variance. The sign of each of
// the first two axes is chosen so that the third moment (skew) of the points
// along it is positive; the third axis is their cross product (a proper
// rotation). Then T = F_target * F_source^-1 maps source points onto target.
//
// Caveats. (1) Symmetric shapes have ~zero skew along an axis, so its sign is
// a coin toss: a 180-degree error about another axis. (2) Two similar
// variances (a round table, a square box seen from above) make the axes
// themselves ill-defined: any rotation about the third axis fits. (3) The
// centroid and covariance of a partial view (the object seen from another
// side in the other mission) differ from the whole object's. register.icp
// refines from this guess and from alternative hypotheses for these cases.
#pragma once

#include <lista/points.hpp>

#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace lista::objreg {

struct PrincipalFrame {
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();  // maps frame coords to world
  Eigen::Vector3d variances = Eigen::Vector3d::Zero();       // decreasing
  Eigen::Vector3d skew = Eigen::Vector3d::Zero();            // normalised third moments (after sign fix)
  bool ambiguous_sign = false;  // |skew| of axis 1 or 2 below the tolerance
  bool ambiguous_axes = false;  // two variances within the tolerance of each other
};

// Throws lista::Error for an empty set.
PrincipalFrame principal_frame(const std::vector<Eigen::Vector3f>& points, double tolerance = 0.05);

// The transform mapping `source` points onto `target` points: p_t = T * p_s.
Eigen::Isometry3d svd_transform(const PrincipalFrame& source, const PrincipalFrame& target);

// The four proper flips of a frame's axes ((+,+,+), (-,-,+), (-,+,-), (+,-,-)):
// hypotheses when the skew signs cannot be trusted.
std::array<Eigen::Matrix3d, 4> axis_flips();

}  // namespace lista::objreg
