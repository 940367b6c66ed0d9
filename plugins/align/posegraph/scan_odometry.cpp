#include "scan_odometry.hpp"

#include <lista/parallel.hpp>
#include <lista_alignkit/cloud_ops.hpp>

#include <cmath>
#include <optional>

namespace lista::align {

namespace {

double rotation_angle(const Eigen::Matrix3d& r) {
  return Eigen::AngleAxisd(Eigen::Quaterniond(r).normalized()).angle();
}

Cloud scan_cloud(const Scan& scan, const ScanEdgeOptions& o) {
  Cloud near;
  if (!scan.points) return near;
  const float r2 = static_cast<float>(o.max_range * o.max_range);
  for (const auto& p : scan.points->xyz)
    if (p.squaredNorm() <= r2) near.push_back(p);
  double voxel = o.registration.voxel;
  Cloud out = voxel_downsample(near, voxel);
  while (out.size() > o.max_points) {
    voxel *= 1.25;
    out = voxel_downsample(near, voxel);
  }
  return out;
}

}  // namespace

std::vector<PoseGraphEdge> scan_registration_edges(const MissionSet& set, const std::vector<size_t>& offsets,
                                                   const ScanEdgeOptions& o, int threads, ScanEdgeReport& report) {
  report = {};
  if (o.neighbours <= 0) return {};
  struct Pair {
    size_t mission, from, to;
  };
  std::vector<Pair> pairs;
  std::vector<std::vector<PreparedCloud>> clouds(set.missions.size());
  for (size_t m = 0; m < set.missions.size(); ++m) {
    const size_t n = set.missions[m].scans.size();
    clouds[m].resize(n);
    for (size_t s = 0; s < n; ++s)
      for (int k = 1; k <= o.neighbours && s + k < n; ++k) pairs.push_back({m, s, s + k});
  }
  std::vector<std::pair<size_t, size_t>> scans;
  for (size_t m = 0; m < set.missions.size(); ++m)
    for (size_t s = 0; s < set.missions[m].scans.size(); ++s) scans.push_back({m, s});
  parallel_for(scans.size(), threads, [&](size_t i) {
    const auto [m, s] = scans[i];
    // Prepared once: each scan is registered up to 2 x neighbours times.
    clouds[m][s] = PreparedCloud(scan_cloud(set.missions[m].scans[s], o), o.registration);
  });
  std::vector<std::optional<PoseGraphEdge>> edges(pairs.size());
  parallel_for(pairs.size(), threads, [&](size_t i) {
    const Pair& p = pairs[i];
    const auto& scans_m = set.missions[p.mission].scans;
    const Eigen::Isometry3d odometry = scans_m[p.from].pose.inverse() * scans_m[p.to].pose;
    const RegistrationResult r =
        register_prepared(clouds[p.mission][p.to], clouds[p.mission][p.from], odometry, o.registration);
    if (!r.converged || std::min(r.overlap, r.reverse_overlap) < o.min_overlap || r.inlier_rmse > o.max_rmse) return;
    const Eigen::Isometry3d change = odometry.inverse() * r.transform;
    if (change.translation().norm() > o.max_translation_change || rotation_angle(change.linear()) > o.max_rotation_change)
      return;
    PoseGraphEdge e;
    e.from = offsets[p.mission] + p.from;
    e.to = offsets[p.mission] + p.to;
    e.measurement = r.transform;
    e.sigma_translation = o.sigma_translation;
    e.sigma_rotation = o.sigma_rotation;
    e.planar = true;
    e.robust = true;
    edges[i] = e;
  });
  std::vector<PoseGraphEdge> out;
  for (auto& e : edges)
    if (e) out.push_back(*e);
  report.tried = pairs.size();
  report.accepted = out.size();
  return out;
}

}  // namespace lista::align
