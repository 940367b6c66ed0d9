#include <lista_alignkit/level.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace lista::alignkit {

namespace {

constexpr double kDeg = M_PI / 180.0;
// Below this the frame is level within what the patches tell: left as is.
constexpr double kMinTilt = 0.5;

double tilt_of(const Eigen::Vector3d& up) { return std::acos(std::clamp(up.z(), -1.0, 1.0)) / kDeg; }

uint64_t cell_key(const Eigen::Vector3d& p, double voxel) {
  // 21 bits a coordinate: +-1 048 576 cells, +-524 km at 0.5 m.
  auto bits = [&](double v) {
    const int64_t i = static_cast<int64_t>(std::floor(v / voxel)) + (int64_t(1) << 20);
    return static_cast<uint64_t>(std::clamp<int64_t>(i, 0, (int64_t(1) << 21) - 1));
  };
  return bits(p.x()) << 42 | bits(p.y()) << 21 | bits(p.z());
}

}  // namespace

void UpEstimator::add(const Eigen::Vector3d& p) {
  Cell& c = cells_[cell_key(p, o_.voxel)];
  ++c.n;
  c.sum += p;
  c.sum_sq += p * p.transpose();
}

LevelEstimate UpEstimator::estimate() const {
  // Normals of the planar cells: thin in one direction (a surface) and
  // spread in the other two (not one ring of a sparse scanner, a line).
  std::vector<Eigen::Vector3d> normals;
  for (const auto& [key, c] : cells_) {
    if (c.n < o_.min_points) continue;
    const Eigen::Vector3d mean = c.sum / c.n;
    const Eigen::Matrix3d cov = c.sum_sq / c.n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
    const Eigen::Vector3d l = es.eigenvalues();  // ascending
    if (l(0) > 0.03 * l(1) || l(1) < 0.1 * l(2)) continue;
    normals.push_back(es.eigenvectors().col(0));
  }
  LevelEstimate e;
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  size_t floor_patches = 0, wall_patches = 0;
  for (const double window : {30.0, 10.0, 5.0}) {
    const double cos_w = std::cos(window * kDeg), sin_w = std::sin(window * kDeg);
    Eigen::Matrix3d floors = Eigen::Matrix3d::Zero(), walls = Eigen::Matrix3d::Zero();
    e.floor_patches = e.wall_patches = 0;
    for (const Eigen::Vector3d& n : normals) {
      const double c = std::abs(n.dot(up));
      if (c >= cos_w) floors += n * n.transpose(), ++e.floor_patches;
      else if (c <= sin_w) walls += n * n.transpose(), ++e.wall_patches;
    }
    // Walls alone fix up only when they face two ways (a corridor's one
    // wall direction leaves a turn about its normal free).
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ws(walls);
    const bool walls_decide = e.wall_patches >= o_.min_patches && ws.eigenvalues()(1) >= 0.1 * ws.eigenvalues()(2);
    // A narrower window that leaves too few keeps the wider one's answer.
    if (e.floor_patches < o_.min_patches && !walls_decide) {
      if (!e.determined) return LevelEstimate{};
      break;
    }
    e.determined = true;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ms(floors - walls);
    Eigen::Vector3d u = ms.eigenvectors().col(2);
    if (u.dot(up) < 0.0) u = -u;
    up = u.normalized();
    floor_patches = e.floor_patches, wall_patches = e.wall_patches;
  }
  e.up = up;
  e.floor_patches = floor_patches, e.wall_patches = wall_patches;
  e.tilt_deg = tilt_of(up);
  return e;
}

LevelEstimate estimate_common_up(const MissionSet& missions, const LevelOptions& o) {
  // The cells are cut level with the frame; a tilted floor's noisy points
  // cut by a cell's top or bottom lean its patch towards the frame's z
  // (measured: a 5 deg tilt read as 4.5 on an OS0-128 office). So the
  // points are binned again in the frame the estimate levels, until that
  // frame is level: there the cuts run along the floors.
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  LevelEstimate e;
  for (int pass = 0; pass < 4; ++pass) {
    UpEstimator est(o);
    for (const Mission& m : missions.missions) {
      const size_t n = m.scans.size();
      const size_t step = std::max<size_t>(1, (n + o.max_scans - 1) / std::max<size_t>(1, o.max_scans));
      for (size_t i = 0; i < n; i += step) {
        if (!m.scans[i].points) continue;
        const Eigen::Isometry3d t = frame * m.sensor_to_common(i);
        for (const Eigen::Vector3f& p : m.scans[i].points->xyz) est.add(t * p.cast<double>());
      }
    }
    const LevelEstimate r = est.estimate();
    if (!r.determined) return pass == 0 ? r : e;
    e = r;
    e.up = (frame.linear().transpose() * r.up).normalized();
    e.tilt_deg = tilt_of(e.up);
    // Level within what is left as is (a level frame costs one pass), or
    // levelled frame and estimate agree.
    if ((pass == 0 && r.tilt_deg < 0.5 * kMinTilt) || (pass > 0 && r.tilt_deg < 0.01)) break;
    frame = levelling_rotation(e.up);
  }
  return e;
}

Eigen::Isometry3d levelling_rotation(const Eigen::Vector3d& up) {
  Eigen::Isometry3d r = Eigen::Isometry3d::Identity();
  r.linear() = Eigen::Quaterniond::FromTwoVectors(up.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return r;
}

void level_common_frame(MissionSet& missions, const LevelConfig& config, Context& ctx, const LevelOptions& o) {
  if (!config.enabled || missions.missions.empty()) return;
  const double max_tilt_deg = config.max_tilt;
  ctx.record("levelled", 0.0);
  if (!missions.origin.isZero()) {
    ctx.info("georeferenced missions: the common frame's z is taken as up, not levelled");
    return;
  }
  const LevelEstimate e = estimate_common_up(missions, o);
  if (!e.determined) {
    ctx.info("too few floors and walls to say which way is up: the common frame is left as it is");
    return;
  }
  ctx.record("level_tilt_deg", e.tilt_deg);
  char line[240];
  if (e.tilt_deg < kMinTilt) return;
  if (e.tilt_deg > max_tilt_deg) {
    std::snprintf(line, sizeof line,
                  "the floors and walls say the common frame is tilted by %.1f deg, more than level.max_tilt "
                  "(%.1f): left as it is; raise level.max_tilt to level it",
                  e.tilt_deg, max_tilt_deg);
    ctx.warn(line);
    return;
  }
  const Eigen::Isometry3d r = levelling_rotation(e.up);
  for (Mission& m : missions.missions) m.to_common = r * m.to_common;
  ctx.record("levelled", 1.0);
  std::snprintf(line, sizeof line,
                "common frame levelled: the maps' floors and walls (%zu and %zu patches) put up %.2f deg off its z",
                e.floor_patches, e.wall_patches, e.tilt_deg);
  ctx.info(line);
}

}  // namespace lista::alignkit
