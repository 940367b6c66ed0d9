#include <lista_objreg/svd_registration.hpp>

#include <lista/error.hpp>

#include <Eigen/Eigenvalues>
#include <cmath>

namespace lista::objreg {

PrincipalFrame principal_frame(const std::vector<Eigen::Vector3f>& points, double tolerance) {
  if (points.empty()) throw Error("cannot register an object with no points");
  const double n = static_cast<double>(points.size());
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : points) c += p.cast<double>();
  c /= n;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector3d q = p.cast<double>() - c;
    cov += q * q.transpose();
  }
  cov /= n;
  // The covariance is symmetric positive semi-definite, so its SVD is its
  // eigen-decomposition; the solver returns ascending values, reversed here.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  const Eigen::Matrix3d u = eig.eigenvectors().rowwise().reverse();
  Eigen::Matrix3d axes = u;  // columns by decreasing variance
  PrincipalFrame f;
  f.variances = eig.eigenvalues().reverse().cwiseMax(0.0);
  // Third moments along each axis decide the axis signs.
  Eigen::Vector3d m3 = Eigen::Vector3d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector3d q = axes.transpose() * (p.cast<double>() - c);
    m3 += q.cwiseProduct(q).cwiseProduct(q);
  }
  m3 /= n;
  for (int k = 0; k < 2; ++k) {
    const double sigma = std::sqrt(std::max(f.variances[k], 1e-30));
    f.skew[k] = m3[k] / (sigma * sigma * sigma);
    if (f.skew[k] < 0.0) axes.col(k) = -axes.col(k), f.skew[k] = -f.skew[k];
    if (f.skew[k] < tolerance) f.ambiguous_sign = true;
  }
  axes.col(2) = axes.col(0).cross(axes.col(1));
  const double sigma2 = std::sqrt(std::max(f.variances[2], 1e-30));
  f.skew[2] = (m3[2] * (axes.col(2).dot(u.col(2)) > 0 ? 1.0 : -1.0)) / (sigma2 * sigma2 * sigma2);
  const double top = std::max(f.variances[0], 1e-30);
  f.ambiguous_axes = (f.variances[0] - f.variances[1]) < tolerance * top ||
                     (f.variances[1] - f.variances[2]) < tolerance * top;
  f.frame.linear() = axes;
  f.frame.translation() = c;
  return f;
}

Eigen::Isometry3d svd_transform(const PrincipalFrame& source, const PrincipalFrame& target) {
  return target.frame * source.frame.inverse();
}

std::array<Eigen::Matrix3d, 4> axis_flips() {
  return {Eigen::Vector3d(1, 1, 1).asDiagonal().toDenseMatrix(),
          Eigen::Vector3d(-1, -1, 1).asDiagonal().toDenseMatrix(),
          Eigen::Vector3d(-1, 1, -1).asDiagonal().toDenseMatrix(),
          Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix()};
}

}  // namespace lista::objreg
