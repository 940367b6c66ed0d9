#include "pose_graph.hpp"

#include <lista/error.hpp>

#include <ceres/ceres.h>

namespace lista::align {

namespace {

// Residual of T_from_to measured vs estimated, whitened: translation error in
// the `from` frame and twice the vector part of the rotation error quaternion.
struct RelativePoseError {
  explicit RelativePoseError(const PoseGraphEdge& e) : t_meas(e.measurement.translation()), q_meas(e.measurement.linear()) {
    const double along = 1.0 / e.sigma_translation, turn = 1.0 / e.sigma_rotation;
    const double up = e.planar ? 0.0 : 1.0 / (e.sigma_height > 0.0 ? e.sigma_height : e.sigma_translation);
    const double tilt = e.planar ? 0.0 : 1.0 / (e.sigma_tilt > 0.0 ? e.sigma_tilt : e.sigma_rotation);
    w_t = Eigen::Vector3d(along, along, up);
    w_r = Eigen::Vector3d(tilt, tilt, turn);
  }

  template <class T>
  bool operator()(const T* q_a_ptr, const T* t_a_ptr, const T* q_b_ptr, const T* t_b_ptr, T* res) const {
    Eigen::Map<const Eigen::Quaternion<T>> q_a(q_a_ptr), q_b(q_b_ptr);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_a(t_a_ptr), t_b(t_b_ptr);
    const Eigen::Quaternion<T> q_a_inv = q_a.conjugate();
    const Eigen::Quaternion<T> q_ab = q_a_inv * q_b;
    const Eigen::Matrix<T, 3, 1> t_ab = q_a_inv * (t_b - t_a);
    const Eigen::Quaternion<T> dq = q_meas.template cast<T>().conjugate() * q_ab;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> r(res);
    r.template head<3>() = (t_ab - t_meas.template cast<T>()).cwiseProduct(w_t.template cast<T>());
    r.template tail<3>() = (T(2.0) * dq.vec()).cwiseProduct(w_r.template cast<T>());
    return true;
  }

  Eigen::Vector3d t_meas;
  Eigen::Quaterniond q_meas;
  Eigen::Vector3d w_t, w_r;  // per axis: 1 / sigma
};

}  // namespace

PoseGraphSummary optimise_pose_graph(std::vector<Eigen::Isometry3d>& nodes, const std::vector<bool>& fixed,
                                     const std::vector<PoseGraphEdge>& edges, const PoseGraphOptions& o) {
  if (fixed.size() != nodes.size()) throw Error("pose graph: one 'fixed' flag per node expected");
  if (std::find(fixed.begin(), fixed.end(), true) == fixed.end())
    throw Error("pose graph: at least one node must be fixed");
  PoseGraphSummary summary;
  if (nodes.empty() || edges.empty()) {
    summary.usable = true;
    return summary;
  }

  std::vector<Eigen::Quaterniond> q(nodes.size());
  std::vector<Eigen::Vector3d> t(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) {
    q[i] = Eigen::Quaterniond(nodes[i].linear()).normalized();
    t[i] = nodes[i].translation();
  }

  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold quaternion_manifold;

  for (const auto& e : edges) {
    if (e.from >= nodes.size() || e.to >= nodes.size() || e.from == e.to)
      throw Error("pose graph: edge between invalid nodes");
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 4, 3, 4, 3>(
        new RelativePoseError(e));
    ceres::LossFunction* loss = nullptr;  // owned by the problem
    if (e.robust && o.loss == RobustLoss::cauchy) loss = new ceres::CauchyLoss(o.loss_scale);
    if (e.robust && o.loss == RobustLoss::huber) loss = new ceres::HuberLoss(o.loss_scale);
    problem.AddResidualBlock(cost, loss, q[e.from].coeffs().data(), t[e.from].data(),
                             q[e.to].coeffs().data(), t[e.to].data());
  }
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (!problem.HasParameterBlock(q[i].coeffs().data())) continue;  // isolated node
    problem.SetManifold(q[i].coeffs().data(), &quaternion_manifold);
    if (fixed[i]) {
      problem.SetParameterBlockConstant(q[i].coeffs().data());
      problem.SetParameterBlockConstant(t[i].data());
    }
  }

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.sparse_linear_algebra_library_type =
      ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ? ceres::SUITE_SPARSE
                                                                           : ceres::EIGEN_SPARSE;
  options.max_num_iterations = o.max_iterations;
  // One thread: Ceres sums cost and gradient per thread, in the order the
  // threads take the residual blocks, and those sums decide the steps, so
  // the poses' last digits could follow the thread count. The graphs are
  // small (one node a keyframe or scan).
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  // The costs the report records, from the whole problem as it stands.
  auto cost_now = [&problem] {
    ceres::Problem::EvaluateOptions one_thread;
    one_thread.num_threads = 1;
    double cost = 0.0;
    problem.Evaluate(one_thread, &cost, nullptr, nullptr, nullptr);
    return cost;
  };
  summary.initial_cost = cost_now();
  ceres::Solver::Summary s;
  ceres::Solve(options, &problem, &s);
  summary.final_cost = cost_now();
  summary.iterations = static_cast<int>(s.iterations.size());
  summary.usable = s.IsSolutionUsable();
  for (size_t i = 0; i < nodes.size(); ++i) {
    nodes[i] = Eigen::Isometry3d::Identity();
    nodes[i].linear() = q[i].normalized().toRotationMatrix();
    nodes[i].translation() = t[i];
  }
  return summary;
}

}  // namespace lista::align
