#include <lista_geometry/bounding_rectangle.hpp>
#include <lista_objfeat/canonical.hpp>

#include <lista/error.hpp>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <unordered_map>

namespace lista::objfeat {
namespace {

using geometry::BoundingRectangle;
using geometry::min_perimeter_rectangle;

Eigen::Vector2d principal_axis(const std::vector<Eigen::Vector3f>& xyz, const Eigen::Vector3f& c) {
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : xyz) {
    Eigen::Vector2d d((p.x() - c.x()), (p.y() - c.y()));
    cov += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  return eig.eigenvectors().col(1);  // largest eigenvalue last
}

// Yaw rotation whose +x is the chosen horizontal axis, sign fixed by skew.
Eigen::Matrix3f yaw_frame(const std::vector<Eigen::Vector3f>& xyz, const Eigen::Vector3f& c, YawFrame frame) {
  const BoundingRectangle rect = frame == YawFrame::bounding_rectangle ? min_perimeter_rectangle(xyz) : BoundingRectangle{};
  // A footprint with no area (a line of points) has no rectangle: fall back.
  Eigen::Vector2d axis = rect.valid ? rect.long_axis : principal_axis(xyz, c);
  double skew = 0.0;
  for (const auto& p : xyz) {
    double t = (p.x() - c.x()) * axis.x() + (p.y() - c.y()) * axis.y();
    skew += t * t * t;
  }
  if (skew < 0.0) axis = -axis;
  Eigen::Matrix3f r = Eigen::Matrix3f::Identity();
  // Rows: canonical axes expressed in the world frame (a proper rotation).
  r(0, 0) = float(axis.x());  r(0, 1) = float(axis.y());
  r(1, 0) = float(-axis.y()); r(1, 1) = float(axis.x());
  return r;
}

}  // namespace

std::vector<CanonicalCloud> make_canonical_samples(const std::vector<Eigen::Vector3f>& xyz, const CanonicalConfig& cfg,
                                                  int samples) {
  if (samples < 1) throw Error("canonical samples must be >= 1");
  if (xyz.empty()) throw Error("cannot describe an object with no points");
  if (cfg.points < 1 || cfg.grid < 1) throw Error("canonical points and grid must be >= 1");

  CanonicalCloud out;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : xyz) sum += p.cast<double>();
  out.centroid = (sum / double(xyz.size())).cast<float>();
  out.rotation = yaw_frame(xyz, out.centroid, cfg.frame);

  std::vector<Eigen::Vector3f> local(xyz.size());
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = -lo;
  for (size_t i = 0; i < xyz.size(); ++i) {
    local[i] = out.rotation * (xyz[i] - out.centroid);
    lo = lo.cwiseMin(local[i]);
    hi = hi.cwiseMax(local[i]);
  }
  out.globals = {hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z(), -lo.z()};
  float cell = std::max((hi - lo).maxCoeff() / float(cfg.grid), 1e-4f);

  // One centroid per occupied voxel; keys are small non-negative ints.
  struct Acc { Eigen::Vector3f sum = Eigen::Vector3f::Zero(); int n = 0; };
  std::unordered_map<uint64_t, Acc> cells;
  cells.reserve(xyz.size());
  for (const auto& p : local) {
    Eigen::Vector3f q = (p - lo) / cell;
    uint64_t ix = uint64_t(std::min(int(q.x()), cfg.grid)), iy = uint64_t(std::min(int(q.y()), cfg.grid)),
             iz = uint64_t(std::min(int(q.z()), cfg.grid));
    Acc& a = cells[(ix << 42) | (iy << 21) | iz];
    a.sum += p;
    ++a.n;
  }
  std::vector<std::pair<uint64_t, Eigen::Vector3f>> centres;
  centres.reserve(cells.size());
  for (const auto& [k, a] : cells) centres.emplace_back(k, a.sum / float(a.n));
  std::sort(centres.begin(), centres.end(), [](const auto& a, const auto& b) { return a.first < b.first; });

  // Seeded selections of exactly cfg.points cells (cycling if too few);
  // selection k uses seed cfg.seed + k, everything above is shared.
  out.points = cfg.points;
  std::vector<CanonicalCloud> result(size_t(samples), out);
  for (int k = 0; k < samples; ++k) {
    std::vector<uint32_t> order(centres.size());
    std::iota(order.begin(), order.end(), 0u);
    std::mt19937_64 rng(cfg.seed + uint64_t(k));
    std::shuffle(order.begin(), order.end(), rng);
    std::vector<float>& features = result[size_t(k)].features;
    features.resize(size_t(cfg.points) * kCanonicalChannels);
    for (int i = 0; i < cfg.points; ++i) {
      const Eigen::Vector3f& p = centres[order[size_t(i) % order.size()]].second;
      float* f = &features[size_t(i) * kCanonicalChannels];
      f[0] = p.x();
      f[1] = p.y();
      f[2] = p.z();
      f[3] = std::hypot(p.x(), p.y());
      f[4] = p.norm();
      f[5] = p.z() - lo.z();
    }
  }
  return result;
}

CanonicalCloud make_canonical(const std::vector<Eigen::Vector3f>& xyz, const CanonicalConfig& cfg) {
  return std::move(make_canonical_samples(xyz, cfg, 1).front());
}

}  // namespace lista::objfeat
