#include <lista_geometry/bounding_rectangle.hpp>
#include <lista_geometry/order_statistics.hpp>
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

// Algebraic (Kasa) circle fit to the cells' x/y: radius and RMS residual,
// radius capped at `cap` (a flat or straight footprint fits a huge circle).
std::pair<float, float> footprint_circle(const std::vector<Eigen::Vector3f>& cells, float cap) {
  if (cells.size() < 3) return {cap, 0.f};
  // x^2 + y^2 + D x + E y + F = 0 in least squares: normal equations.
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& p : cells) {
    const Eigen::Vector3d row(p.x(), p.y(), 1.0);
    a += row * row.transpose();
    b -= row * (double(p.x()) * p.x() + double(p.y()) * p.y());
  }
  const Eigen::Vector3d sol = a.ldlt().solve(b);
  const Eigen::Vector2d centre(-sol.x() / 2, -sol.y() / 2);
  const double r2 = centre.squaredNorm() - sol.z();
  if (!std::isfinite(r2) || r2 <= 0.0 || std::sqrt(r2) > cap) return {cap, 0.f};
  const double r = std::sqrt(r2);
  double sq = 0.0;
  for (const auto& p : cells) {
    const double d = (Eigen::Vector2d(p.x(), p.y()) - centre).norm() - r;
    sq += d * d;
  }
  return {float(r), float(std::min(std::sqrt(sq / double(cells.size())), double(cap)))};
}

// q-th to (1-q)-th quantile spread of the cells along one axis.
float spread(const std::vector<Eigen::Vector3f>& cells, int axis, double q) {
  std::vector<float> v(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) v[i] = cells[i][axis];
  const size_t lo = size_t(q * double(v.size() - 1) + 0.5), hi = v.size() - 1 - lo;
  const float low = geometry::kth_smallest(v, lo);
  return geometry::kth_smallest(v, hi) - low;
}

}  // namespace

std::vector<CanonicalCloud> make_canonical_samples(const std::vector<Eigen::Vector3f>& xyz, const CanonicalConfig& cfg,
                                                  int samples, float floor_z) {
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

  std::vector<Eigen::Vector3f> cell_points(centres.size());
  for (size_t i = 0; i < centres.size(); ++i) cell_points[i] = centres[i].second;
  const Eigen::Vector3f extent = hi - lo;
  // Heights are measured from `base`: the floor (in the centred frame; the
  // rotation is about z) when known and used, else the lowest point. A floor
  // above the lowest point (points under a floor estimate) is clamped to it.
  const bool use_floor = cfg.floor && std::isfinite(floor_z);
  const float base = use_floor ? std::min(floor_z - out.centroid.z(), lo.z()) : lo.z();
  const auto [radius, residual] = footprint_circle(cell_points, 2.f * std::max(extent.x(), extent.y()));
  out.globals = {extent.x(),  extent.y(), extent.z(), -base, radius, residual, spread(cell_points, 0, 0.02),
                 spread(cell_points, 1, 0.02), spread(cell_points, 2, 0.02), lo.z() - base};

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
      f[5] = p.z() - base;
    }
  }
  return result;
}

CanonicalCloud make_canonical(const std::vector<Eigen::Vector3f>& xyz, const CanonicalConfig& cfg, float floor_z) {
  return std::move(make_canonical_samples(xyz, cfg, 1, floor_z).front());
}

}  // namespace lista::objfeat
