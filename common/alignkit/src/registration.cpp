#include <lista_alignkit/registration.hpp>

#include <lista/error.hpp>
#include <lista_pcl/fast_kdtree.hpp>
#include <lista_pcl/quiet.hpp>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lista::alignkit {

namespace {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;
using Gicp = pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>;
constexpr int kCovarianceNeighbours = 10;

// PCL computes GICP covariances inside align(); this exposes that step so a
// cloud's covariances are computed once, not per registration.
struct CovarianceGicp : Gicp {
  Gicp::MatricesVectorPtr covariances_of(const PclCloud::ConstPtr& cloud, const pcl_search::FastKdTree::Ptr& tree) {
    setCorrespondenceRandomness(kCovarianceNeighbours);
    auto out = std::make_shared<Gicp::MatricesVector>();
    computeCovariances<pcl::PointXYZ>(cloud, tree, *out);
    return out;
  }
};

// The normal of every point's local plane, or NaN where it has none: the
// spread of its 10 nearest points, from a closed-form eigen-solver and reused
// buffers, taken about the mean in double.
//
// Unlike PCL's GICP planes, a neighbourhood that is a strip rather than a
// patch (its second spread under kMinPlaneAspect of its first) is widened to
// 3x the points, which on a sparse scanner reaches the next ring; a strip
// even so gets no plane. The 10 nearest points of a sparse scanner's floor or
// wall point lie along one ring, and the "normal" of a line is whichever way
// noise tips it, often across the ring within the surface: rings then pull
// onto rings wherever the scans were taken.
std::vector<Eigen::Vector3f> plane_normals(const PclCloud& cloud, const pcl_search::FastKdTree& tree) {
  constexpr double kMinPlaneAspect = 0.3;  // second / first eigenvalue of the spread
  constexpr int kWide = 3 * kCovarianceNeighbours;
  std::vector<Eigen::Vector3f> out(cloud.size(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  pcl::Indices idx;
  std::vector<float> d2;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  // The spread of point i's k nearest points; false if fewer than 3.
  auto spread_of = [&](size_t i, int k) {
    const int n = tree.nearestKSearch(cloud[i], k, idx, d2);
    if (n < 3) return false;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int j = 0; j < n; ++j) mean += cloud[static_cast<size_t>(idx[j])].getVector3fMap().cast<double>();
    mean /= n;
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector3d d = cloud[static_cast<size_t>(idx[j])].getVector3fMap().cast<double>() - mean;
      spread.noalias() += d * d.transpose();
    }
    solver.computeDirect(spread / n);
    return true;
  };
  auto is_strip = [&] { return solver.eigenvalues()(1) < kMinPlaneAspect * solver.eigenvalues()(2); };
  for (size_t i = 0; i < cloud.size(); ++i) {
    if (!spread_of(i, kCovarianceNeighbours)) continue;
    if (is_strip() && (!spread_of(i, kWide) || is_strip())) continue;  // a strip even so: no plane
    out[i] = solver.eigenvectors().col(0).cast<float>();  // smallest eigenvalue first
  }
  return out;
}

// The covariance of every point as PCL's GICP defines it (its plane: 1 along
// the plane, 1e-3 across it; I - (1 - 1e-3) n n^T), from plane_normals; a
// point without a plane gets I, a weak point-to-point pull. VLP-16 scan pairs
// of a hall, scored against the truth (`lista-bench registration --dataset`,
// docs/bench/alignment.md): median error 55 -> 3.3 mm and 0.82 -> 0.06
// degrees against the same solver with PCL's planes.
Gicp::MatricesVectorPtr plane_covariances(const std::vector<Eigen::Vector3f>& normals) {
  constexpr double kAcross = 1e-3;  // PCL's gicp_epsilon
  auto out = std::make_shared<Gicp::MatricesVector>(normals.size(), Eigen::Matrix3d::Identity());
  for (size_t i = 0; i < normals.size(); ++i) {
    if (!normals[i].allFinite()) continue;
    const Eigen::Vector3d n = normals[i].cast<double>();
    (*out)[i] = Eigen::Matrix3d::Identity() - (1.0 - kAcross) * n * n.transpose();
  }
  return out;
}

enum class Covariances { none, ours, pcl };

}  // namespace

struct PreparedCloud::Impl {
  // One resolution: cloud, k-d tree, GICP covariances.
  struct Level {
    PclCloud::Ptr cloud;
    pcl_search::FastKdTree::Ptr tree;
    Gicp::MatricesVectorPtr covariances;  // GICP only
    std::vector<Eigen::Vector3f> normals; // fine level only; NaN where no plane

    Level() = default;
    Level(const Cloud& points, Covariances kind, bool with_normals)
        : cloud(std::make_shared<PclCloud>()), tree(std::make_shared<pcl_search::FastKdTree>()) {
      cloud->resize(points.size());
      for (size_t i = 0; i < points.size(); ++i) cloud->points[i].getVector3fMap() = points[i];
      if (points.empty()) return;
      tree->setInputCloud(cloud);
      if (points.size() < kCovarianceNeighbours) return;
      std::vector<Eigen::Vector3f> planes;
      if (with_normals || kind == Covariances::ours) planes = plane_normals(*cloud, *tree);
      if (kind == Covariances::ours) covariances = plane_covariances(planes);
      if (with_normals) normals = std::move(planes);
      if (kind == Covariances::pcl) covariances = CovarianceGicp().covariances_of(cloud, tree);
    }
    bool usable() const { return cloud && cloud->size() >= 20; }
  };
  Level coarse, fine;
};

namespace {

using Level = PreparedCloud::Impl::Level;

double coarse_voxel_of(const RegistrationOptions& o) { return std::max(o.voxel, o.coarse_distance / 4.0); }

Covariances covariances_for(const RegistrationOptions& o) {
  switch (o.method) {
    case RegistrationMethod::gicp_gn: return Covariances::ours;
    case RegistrationMethod::gicp: return Covariances::pcl;
    case RegistrationMethod::icp: break;
  }
  return Covariances::none;
}

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

// Generalized ICP (Segal et al. 2009, the cost PCL's GICP minimises: each
// pair's residual weighted by (C_target + R C_source R^T)^-1) solved by
// Gauss-Newton, one linearisation per correspondence update, as small_gicp
// and fast_gicp solve it. PCL runs a BFGS with line searches to convergence
// after every update, a third of align.posegraph's time on a VLP-16 hall
// (docs/bench/alignment.md, 2026-11-29; opt-in, method "gicp_gn"). Like
// PCL's, `converged` is false only when the solve fails (under 6 pairs, a
// singular system); reaching `max_iterations` counts as converged and is
// judged by the caller's gates.
Eigen::Isometry3d gicp_gauss_newton(const Level& source, const Level& target, const Eigen::Isometry3d& guess,
                                    double max_distance, int max_iterations, bool& converged) {
  constexpr double kRotationEpsilon = 2e-4;     // rad per step: 4 mm at 20 m
  constexpr double kTranslationEpsilon = 1e-4;  // m per step
  constexpr size_t kMinPairs = 6;
  const auto& src = source.cloud->points;
  const auto& tgt = target.cloud->points;
  const auto& src_cov = *source.covariances;
  const auto& tgt_cov = *target.covariances;
  const float max_sq = static_cast<float>(max_distance * max_distance);
  Eigen::Isometry3d t = guess;
  converged = false;
  std::vector<int> last(src.size(), -1);  // each point's partner in the step before: the next search's bound
  for (int it = 0; it < max_iterations; ++it) {
    Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    size_t pairs = 0;
    const Eigen::Matrix3d r = t.linear();
    for (size_t i = 0; i < src.size(); ++i) {
      const Eigen::Vector3d q = t * src[i].getVector3fMap().cast<double>();
      pcl::PointXYZ query;
      query.getVector3fMap() = q.cast<float>();
      float d2 = 0.0f;
      const int j = last[i] = target.tree->nearest(query, d2, max_sq, last[i]);
      if (j < 0) continue;
      const Eigen::Matrix3d w = (tgt_cov[static_cast<size_t>(j)] + r * src_cov[i] * r.transpose()).inverse();
      const Eigen::Vector3d e = tgt[static_cast<size_t>(j)].getVector3fMap().cast<double>() - q;
      // e(xi) = target - (q + w x q + v): d e / d(w, v) = [ [q]x, -I ].
      Eigen::Matrix<double, 3, 6> jac;
      jac.leftCols<3>() = skew(q);
      jac.rightCols<3>() = -Eigen::Matrix3d::Identity();
      const Eigen::Matrix<double, 6, 3> jtw = jac.transpose() * w;
      h.noalias() += jtw * jac;
      b.noalias() += jtw * e;
      ++pairs;
    }
    if (pairs < kMinPairs) return converged = false, t;
    const Eigen::Matrix<double, 6, 1> step = h.ldlt().solve(-b);
    if (!step.allFinite()) return converged = false, t;
    const Eigen::Vector3d w = step.head<3>();
    const double angle = w.norm();
    const Eigen::Matrix3d dr =
        angle > 0.0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
    const Eigen::Vector3d moved_to = dr * t.translation() + step.tail<3>();
    const double shift = (moved_to - t.translation()).norm();
    t.linear() = dr * t.linear();
    t.translation() = moved_to;
    converged = true;
    // The step's rotation and how far it moved the translation (rotation
    // about the origin included), as PCL compares successive transforms.
    if (angle < kRotationEpsilon && shift < kTranslationEpsilon) break;
  }
  return t;
}

Eigen::Isometry3d run_stage(const Level& source, const Level& target, const Eigen::Isometry3d& guess,
                            double max_distance, const RegistrationOptions& o, bool& converged) {
  if (o.method == RegistrationMethod::gicp_gn && source.covariances && target.covariances)
    return gicp_gauss_newton(source, target, guess, max_distance, o.max_iterations, converged);
  std::unique_ptr<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>> reg;
  const bool gicp = o.method != RegistrationMethod::icp;
  if (gicp) {
    auto g = std::make_unique<Gicp>();
    g->setCorrespondenceRandomness(kCovarianceNeighbours);
    g->setRotationEpsilon(2e-4);  // rotation-matrix entries; 2e-4 is 4 mm at 20 m
    reg = std::move(g);
  } else {
    reg = std::make_unique<pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>>();
  }
  // The prepared trees (single-query-fast, see fast_kdtree.hpp) already hold
  // their clouds: PCL must not rebuild them.
  reg->setSearchMethodSource(source.tree, true);
  reg->setSearchMethodTarget(target.tree, true);
  reg->setInputSource(source.cloud);
  reg->setInputTarget(target.cloud);
  if (gicp) {  // after the clouds: setting a cloud drops its covariances
    auto* g = static_cast<Gicp*>(reg.get());
    if (source.covariances) g->setSourceCovariances(source.covariances);
    if (target.covariances) g->setTargetCovariances(target.covariances);
  }
  reg->setMaxCorrespondenceDistance(max_distance);
  reg->setMaximumIterations(o.max_iterations);
  // Stop when a step moves less than 0.1 mm. PCL's GICP compares the plain
  // translation step with the epsilon, its ICP the squared one.
  reg->setTransformationEpsilon(gicp ? 1e-4 : 1e-8);
  reg->setEuclideanFitnessEpsilon(1e-8);
  PclCloud aligned;
  {
    pcl_convert::QuietPcl quiet;  // "not enough correspondences" is judged below, not printed
    reg->align(aligned, guess.matrix().cast<float>());
  }
  converged = reg->hasConverged();
  Eigen::Isometry3d result(reg->getFinalTransformation().cast<double>());
  // Re-orthonormalise: float accumulation leaves a slightly skewed rotation.
  result.linear() = Eigen::Quaterniond(result.linear()).normalized().toRotationMatrix();
  return result;
}

// Points of `from` (moved by t) with a point of `to` within max_distance:
// their count and the sum of their squared distances; and of those whose
// nearest point has a plane (`to`'s normals), the count and the sum of their
// squared distances along its normal.
struct Hits {
  size_t count = 0;
  double sum_sq = 0.0;
  double plane_sum_sq = 0.0;
  size_t on_planes = 0;
};
Hits hits(const Level& from, const Level& to, const Eigen::Isometry3d& t, double max_distance) {
  const Eigen::Isometry3f tf = t.cast<float>();
  const float max_sq = static_cast<float>(max_distance * max_distance);
  const bool planes = !to.normals.empty();
  Hits h;
  for (const auto& p : from.cloud->points) {
    pcl::PointXYZ q;
    q.getVector3fMap() = tf * p.getVector3fMap();
    float d2 = 0.0f;
    const int j = to.tree->nearest(q, d2, max_sq);
    if (j < 0) continue;
    ++h.count;
    h.sum_sq += d2;
    if (!planes) continue;
    const Eigen::Vector3f& n = to.normals[static_cast<size_t>(j)];
    if (!n.allFinite()) continue;  // a strip or a corner: no plane
    const float along = n.dot(q.getVector3fMap() - to.cloud->points[static_cast<size_t>(j)].getVector3fMap());
    h.plane_sum_sq += along * along;
    ++h.on_planes;
  }
  return h;
}

double share(size_t n, const Level& of) { return of.cloud->empty() ? 0.0 : static_cast<double>(n) / of.cloud->size(); }

}  // namespace

PreparedCloud::PreparedCloud(const Cloud& points, const RegistrationOptions& o) {
  auto impl = std::make_shared<Impl>();
  const Covariances kind = covariances_for(o);
  impl->fine = Level(points, kind, o.measure_planes);
  impl->coarse = Level(voxel_downsample(points, coarse_voxel_of(o)), kind, false);
  impl_ = std::move(impl);
}

size_t PreparedCloud::size() const { return impl_ ? impl_->fine.cloud->size() : 0; }

RegistrationResult register_prepared(const PreparedCloud& source, const PreparedCloud& target,
                                     const Eigen::Isometry3d& guess, const RegistrationOptions& o) {
  RegistrationResult result;
  if (!source.impl_ || !target.impl_ || !source.impl_->fine.usable() || !target.impl_->fine.usable()) return result;
  const PreparedCloud::Impl& src = *source.impl_;
  const PreparedCloud::Impl& tgt = *target.impl_;

  // Coarse stage on a sparser cloud reaches further; fine stage settles it.
  bool converged = false;
  Eigen::Isometry3d t = guess;
  if (src.coarse.usable() && tgt.coarse.usable()) {
    t = run_stage(src.coarse, tgt.coarse, guess, o.coarse_distance, o, converged);
    // Most wrong candidates show here, at a fraction of the fine stage's cost.
    if (o.min_coarse_overlap > 0.0) {
      const double d = std::max(coarse_voxel_of(o), o.inlier_distance);
      const double ov = std::min(share(hits(src.coarse, tgt.coarse, t, d).count, src.coarse),
                                 share(hits(tgt.coarse, src.coarse, t.inverse(), d).count, tgt.coarse));
      if (ov < o.min_coarse_overlap) {
        result.transform = t;
        result.overlap = result.reverse_overlap = ov;
        return result;
      }
    }
  }
  t = run_stage(src.fine, tgt.fine, t, o.fine_distance, o, converged);
  result.converged = converged;
  result.transform = t;
  const Hits h = hits(src.fine, tgt.fine, t, o.inlier_distance);
  result.overlap = share(h.count, src.fine);
  if (h.count) {
    result.inlier_rmse = std::sqrt(h.sum_sq / static_cast<double>(h.count));
  }
  if (h.on_planes) result.plane_rmse = std::sqrt(h.plane_sum_sq / static_cast<double>(h.on_planes));
  result.reverse_overlap = share(hits(tgt.fine, src.fine, t.inverse(), o.inlier_distance).count, tgt.fine);
  return result;
}

bool RegistrationGates::accept(const RegistrationResult& r, const Eigen::Isometry3d& guess, bool both_ways) const {
  const double overlap = both_ways ? std::min(r.overlap, r.reverse_overlap) : r.overlap;
  if (!r.converged || overlap < min_overlap) return false;
  if (max_rmse > 0.0 && r.inlier_rmse > max_rmse) return false;
  if (max_plane_rmse > 0.0 && !(r.plane_rmse <= max_plane_rmse)) return false;  // NaN: not measured
  const Eigen::Isometry3d change = guess.inverse() * r.transform;
  return change.translation().norm() <= max_translation_change &&
         rotation_angle(change.linear()) <= max_rotation_change;
}

RegistrationGates scan_pair_gates(RegistrationMethod method, double min_overlap, double max_rmse,
                                  double max_plane_rmse) {
  RegistrationGates g;
  g.min_overlap = min_overlap;
  const bool planes = method == RegistrationMethod::gicp_gn;
  g.max_rmse = planes ? 0.0 : max_rmse;
  g.max_plane_rmse = planes ? max_plane_rmse : 0.0;
  return g;
}

RegistrationResult register_clouds(const Cloud& source, const Cloud& target,
                                   const Eigen::Isometry3d& guess, const RegistrationOptions& o) {
  if (source.size() < 20 || target.size() < 20) return {};
  return register_prepared(PreparedCloud(source, o), PreparedCloud(target, o), guess, o);
}

}  // namespace lista::alignkit
