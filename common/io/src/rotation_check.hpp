// Internal: whether a 3x3 matrix is a rotation, shared by the readers of
// poses (poses.txt, KITTI) and of report.json / ground_truth.json matrices.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>

#include <string>

namespace lista::io::detail {

// |R^T R - I| allowed: text files carry 6-17 digits.
constexpr double kOrthoTolerance = 1e-3;

// Empty if R is a rotation (orthonormal within kOrthoTolerance, det +1),
// else why not.
inline std::string rotation_problem(const Eigen::Matrix3d& R) {
  const double err = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (err > kOrthoTolerance) return "rotation is not orthonormal (|R^T R - I| = " + std::to_string(err) + ")";
  if (R.determinant() < 0) return "rotation is a reflection (det R = -1): a mirrored axis, e.g. a left-handed frame";
  return {};
}

}  // namespace lista::io::detail
