#include "scan_odometry.hpp"

#include <lista/parallel.hpp>
#include <lista_alignkit/cloud_ops.hpp>

#include <algorithm>
#include <cmath>
#include <optional>

namespace lista::align {

// The edges constrain x, y and yaw only, which the ground cannot tell; in an
// outdoor scan it holds most of the points (the scan_points budget, the
// overlap and RMSE gates) and a sparse sensor's ground rings, concentric
// about each sensor, match ring to ring whatever the step.
Cloud above_ground(const Cloud& near, const Eigen::Isometry3d& pose, double clearance) {
  if (clearance <= 0.0 || near.empty()) return near;
  const Eigen::Matrix3f level = pose.linear().cast<float>();
  std::vector<float> height(near.size());
  for (size_t i = 0; i < near.size(); ++i) height[i] = (level * near[i]).z();
  std::vector<float> sorted = height;
  const size_t k = sorted.size() / 50;
  std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(k), sorted.end());
  const float cut = sorted[k] + static_cast<float>(clearance);
  Cloud above;
  for (size_t i = 0; i < near.size(); ++i)
    if (height[i] > cut) above.push_back(near[i]);
  return above.size() >= 100 ? above : near;
}

namespace {

Cloud scan_cloud(const Scan& scan, const ScanEdgeOptions& o) {
  Cloud near;
  if (!scan.points) return near;
  const float r2 = static_cast<float>(o.max_range * o.max_range);
  for (const auto& p : scan.points->xyz)
    if (p.squaredNorm() <= r2) near.push_back(p);
  near = above_ground(near, scan.pose, o.ground_clearance);
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
                                                   const ScanEdgeOptions& o, int threads, ScanEdgeReport& report,
                                                   const std::function<bool()>& cancelled,
                                                   const std::function<void()>& on_cancel) {
  auto stop = [&] { return cancelled && cancelled(); };
  report = {};
  if (o.neighbours <= 0) return {};
  // Scans are prepared (k-d trees, GICP covariances: ~100 bytes a point)
  // block by block, so memory stays bounded however long a mission is.
  constexpr size_t kBlock = 64;
  std::vector<std::optional<PoseGraphEdge>> edges;
  std::vector<size_t> mission_end(set.missions.size());  // end of each mission's edges
  for (size_t m = 0; m < set.missions.size(); ++m) {
    const auto& scans = set.missions[m].scans;
    // Neighbours are the next scans that hold points: an empty scan (a
    // sensor dropout, a scan io.missions did not read) is stepped over.
    std::vector<size_t> held;
    for (size_t s = 0; s < scans.size(); ++s)
      if (scans[s].points && !scans[s].points->empty()) held.push_back(s);
    for (size_t first = 0; first < held.size(); first += kBlock) {
      if (stop() && on_cancel) on_cancel();
      const size_t last = std::min(held.size(), first + kBlock + size_t(o.neighbours));  // exclusive
      std::vector<PreparedCloud> clouds(last - first);
      // Prepared once: each scan is registered up to 2 x neighbours times.
      parallel_for(clouds.size(), threads,
                   [&](size_t i) { clouds[i] = PreparedCloud(scan_cloud(scans[held[first + i]], o), o.registration); });
      std::vector<std::pair<size_t, size_t>> pairs;  // (from, to) positions in `held`
      for (size_t p = first; p < std::min(held.size(), first + kBlock); ++p)
        for (size_t k = 1; k <= size_t(o.neighbours) && p + k < held.size(); ++k) pairs.push_back({p, p + k});
      const size_t offset = edges.size();
      edges.resize(offset + pairs.size());
      parallel_for(pairs.size(), threads, [&](size_t i) {
        if (stop()) return;
        const auto [from_at, to_at] = pairs[i];
        const size_t from = held[from_at], to = held[to_at];
        const Eigen::Isometry3d odometry = scans[from].pose.inverse() * scans[to].pose;
        const RegistrationResult r =
            register_prepared(clouds[to_at - first], clouds[from_at - first], odometry, o.registration);
        if (!r.converged || std::min(r.overlap, r.reverse_overlap) < o.min_overlap || r.inlier_rmse > o.max_rmse) return;
        const Eigen::Isometry3d change = odometry.inverse() * r.transform;
        if (change.translation().norm() > o.max_translation_change ||
            rotation_angle(change.linear()) > o.max_rotation_change)
          return;
        PoseGraphEdge e;
        e.from = offsets[m] + from;
        e.to = offsets[m] + to;
        e.measurement = r.transform;
        e.sigma_translation = o.sigma_translation;
        e.sigma_rotation = o.sigma_rotation;
        e.planar = true;
        e.robust = true;
        edges[offset + i] = e;
      });
    }
    mission_end[m] = edges.size();
  }
  if (stop() && on_cancel) on_cancel();
  std::vector<PoseGraphEdge> out;
  for (auto& e : edges)
    if (e) out.push_back(*e);
  report.tried = edges.size();
  report.accepted = out.size();
  for (size_t m = 0, begin = 0; m < mission_end.size(); begin = mission_end[m++]) {
    report.tried_per_mission.push_back(mission_end[m] - begin);
    const auto from = edges.begin() + long(begin), to = edges.begin() + long(mission_end[m]);
    report.accepted_per_mission.push_back(size_t(std::count_if(from, to, [](const auto& e) { return e.has_value(); })));
  }
  return out;
}

}  // namespace lista::align
