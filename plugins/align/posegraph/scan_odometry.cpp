#include "scan_odometry.hpp"

#include <lista/parallel.hpp>
#include <lista_alignkit/cloud_ops.hpp>
#include <lista_geometry/stations.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <optional>

namespace lista::align {

using namespace alignkit;  // common/alignkit: clouds, registration, levelling

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
  const float cut = geometry::kth_smallest(sorted, sorted.size() / 50) + static_cast<float>(clearance);
  Cloud above;
  for (size_t i = 0; i < near.size(); ++i)
    if (height[i] > cut) above.push_back(near[i]);
  return above.size() >= 100 ? above : near;
}

namespace {

// The points a registration uses: near the sensor, the ground left out if asked.
Cloud near_points(const Scan& scan, const ScanEdgeOptions& o) {
  if (!scan.points) return {};
  return above_ground(within_range(scan.points->xyz, o.max_range), scan.pose, o.ground_clearance);
}

Cloud downsampled(const Cloud& near, const ScanEdgeOptions& o, size_t max_points) {
  return voxel_downsample_at_most(near, o.registration.voxel, max_points);
}

}  // namespace

Cloud scan_cloud(const Scan& scan, const ScanEdgeOptions& o) { return downsampled(near_points(scan, o), o, o.max_points); }

// The registration, if it passes the gates; `both_ways`: the target's
// overlap with the source counts too (not for a local map, which reaches
// beyond what one scan sees).
std::optional<Eigen::Isometry3d> gated_registration(const PreparedCloud& source, const PreparedCloud& target,
                                                    const Eigen::Isometry3d& odometry, const ScanEdgeOptions& o,
                                                    bool both_ways) {
  const RegistrationResult r = register_prepared(source, target, odometry, o.registration);
  if (!o.gates.accept(r, odometry, both_ways)) return std::nullopt;
  return r.transform;
}

PoseGraphEdge scan_edge(size_t from, size_t to, const Eigen::Isometry3d& measurement, const ScanEdgeOptions& o) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.measurement = measurement;
  e.sigma_translation = o.sigma_translation;
  e.sigma_rotation = o.sigma_rotation;
  e.planar = true;
  e.robust = o.robust;
  return e;
}

ScanEdgeOptions station_edge_options(const ScanEdgeOptions& o) {
  ScanEdgeOptions s = o;
  s.gates.min_overlap = o.station_min_overlap;
  s.registration.min_coarse_overlap = 0.6 * o.station_min_overlap;
  // Nor under the robust loss: a robot walks metres between stations, so
  // the odometry starts tens of the edges' sigmas from what they measure,
  // where a robust loss scaled in those sigmas would discount exactly the
  // correction (a hall's stations 22-30 m apart kept 0.35-0.85 deg of yaw).
  s.robust = false;
  return s;
}

namespace {

// Scan-to-map (o.map_scans > 1): the mission's scans in order, each
// registered onto a local map of the map_scans scans before it, placed where
// the registrations before put them; the odometry would blur the map by its
// per-step error, which is what the edges are to measure. One edge per
// scan (`held`: the scans that hold points), from the scan before.
std::vector<std::optional<PoseGraphEdge>> scan_to_map_edges(const std::vector<Scan>& scans,
                                                            const std::vector<size_t>& held, size_t node_offset,
                                                            const ScanEdgeOptions& o,
                                                            const std::function<bool()>& stop) {
  std::vector<std::optional<PoseGraphEdge>> edges;
  if (held.empty()) return edges;
  const size_t span = static_cast<size_t>(o.map_scans);
  std::deque<std::pair<Eigen::Isometry3d, Cloud>> window;  // placed pose, points in the scan's frame
  window.emplace_back(scans[held[0]].pose, scan_cloud(scans[held[0]], o));
  for (size_t k = 1; k < held.size(); ++k) {
    if (stop()) break;
    const size_t before = held[k - 1], scan = held[k];
    const Eigen::Isometry3d odometry = scans[before].pose.inverse() * scans[scan].pose;
    const Eigen::Isometry3d to_before = window.back().first.inverse();
    Cloud map;
    for (const auto& [pose, cloud] : window) {
      const Eigen::Isometry3f t = (to_before * pose).cast<float>();
      for (const auto& x : cloud) map.push_back(t * x);
    }
    Cloud points = scan_cloud(scans[scan], o);
    const std::optional<Eigen::Isometry3d> step =
        gated_registration(PreparedCloud(points, o.registration),
                           PreparedCloud(downsampled(map, o, o.max_points * span), o.registration), odometry, o, false);
    edges.emplace_back();
    if (step) edges.back() = scan_edge(node_offset + before, node_offset + scan, *step, o);
    window.emplace_back(window.back().first * (step ? *step : odometry), std::move(points));
    if (window.size() > span) window.pop_front();
  }
  return edges;
}

// Scan to scan: each scan onto each of the next o.neighbours scans. Scans
// are prepared (k-d trees, GICP covariances: ~100 bytes a point) block by
// block, so memory stays bounded however long a mission is.
std::vector<std::optional<PoseGraphEdge>> scan_to_scan_edges(const std::vector<Scan>& scans,
                                                             const std::vector<size_t>& held, size_t node_offset,
                                                             const ScanEdgeOptions& o, int threads,
                                                             const std::function<bool()>& stop) {
  constexpr size_t kBlock = 64;
  std::vector<std::optional<PoseGraphEdge>> edges;
  for (size_t first = 0; first < held.size() && !stop(); first += kBlock) {
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
      const auto step = gated_registration(clouds[to_at - first], clouds[from_at - first], odometry, o, true);
      if (step) edges[offset + i] = scan_edge(node_offset + from, node_offset + to, *step, o);
    });
  }
  return edges;
}

// The share of a mission's scan pairs that must register for its scan
// edges to stay scan to scan: half, three quarters when they are judged
// along planes (RegistrationGates::max_plane_rmse). Judged point to point,
// a sparse scanner's pairs fail on their ring gaps and local maps fill
// them. Along planes 58-62 % of a VLP-16's pairs on an open site pass, and
// the steps no passing pair spans kept the odometry's bias: its poses ended
// 0.14-0.19 m off, against 0.06 m on local maps; a hall's pairs pass 98 %,
// an XT32's or OS0-128's 99-100 % (docs/bench/alignment.md, 2026-11-30).
double min_pair_share(const RegistrationGates& gates) { return gates.max_plane_rmse > 0.0 ? 0.75 : 0.5; }

size_t accepted(const std::vector<std::optional<PoseGraphEdge>>& edges) {
  return size_t(std::count_if(edges.begin(), edges.end(), [](const auto& e) { return e.has_value(); }));
}

}  // namespace

std::vector<PoseGraphEdge> scan_registration_edges(const MissionSet& set, const std::vector<size_t>& offsets,
                                                   const ScanEdgeOptions& options, int threads,
                                                   ScanEdgeReport& report, const std::function<bool()>& cancelled,
                                                   const std::function<void()>& on_cancel) {
  ScanEdgeOptions o = options;
  o.registration.measure_planes = o.gates.max_plane_rmse > 0.0;
  auto stop = [&] { return cancelled && cancelled(); };
  report = {};
  if (o.neighbours <= 0) return {};
  const size_t missions = set.missions.size();
  std::vector<std::vector<std::optional<PoseGraphEdge>>> edges(missions);
  std::vector<std::vector<size_t>> held(missions);
  report.scan_to_map.assign(missions, o.map_scans > 1 && o.map_use == MapUse::always);
  report.pairs_tried.assign(missions, 0);
  report.pairs_accepted.assign(missions, 0);
  report.stations.assign(missions, false);
  // Stations' pairs are judged as whole maps are (GlobalSearchOptions::
  // min_overlap): the overlap of the smaller side, at the whole-map bar.
  const ScanEdgeOptions station_options = station_edge_options(o);
  auto options_of = [&](size_t m) -> const ScanEdgeOptions& { return report.stations[m] ? station_options : o; };
  for (size_t m = 0; m < missions; ++m) {
    // Neighbours are the next scans that hold points: an empty scan (a
    // sensor dropout, a scan io.missions did not read) is stepped over.
    for (size_t s = 0; s < set.missions[m].scans.size(); ++s)
      if (set.missions[m].scans[s].points && !set.missions[m].scans[s].points->empty()) held[m].push_back(s);
    report.stations[m] = held[m].size() > 1 && geometry::scanned_from_stations(set.missions[m]);
    if (report.scan_to_map[m]) continue;
    edges[m] = scan_to_scan_edges(set.missions[m].scans, held[m], offsets[m], options_of(m), threads, stop);
    if (stop() && on_cancel) on_cancel();
    report.pairs_tried[m] = edges[m].size();
    report.pairs_accepted[m] = accepted(edges[m]);
    // Fewer than min_pair_share of the pairs register: the scans are too
    // sparse for one another (a 16-beam scanner outdoors), and the steps no
    // pair spans keep the odometry's bias; local maps fill the gaps.
    report.scan_to_map[m] = o.map_scans > 1 && o.map_use == MapUse::when_pairs_fail &&
                            static_cast<double>(report.pairs_accepted[m]) <
                                min_pair_share(o.gates) * static_cast<double>(report.pairs_tried[m]);
  }
  // Scan-to-map is sequential within a mission: the missions side by side.
  parallel_for(missions, threads, [&](size_t m) {
    if (report.scan_to_map[m])
      edges[m] = scan_to_map_edges(set.missions[m].scans, held[m], offsets[m], options_of(m), stop);
  });
  if (stop() && on_cancel) on_cancel();
  std::vector<PoseGraphEdge> out;
  for (size_t m = 0; m < missions; ++m) {
    report.tried_per_mission.push_back(edges[m].size());
    report.accepted_per_mission.push_back(accepted(edges[m]));
    report.tried += edges[m].size();
    for (auto& e : edges[m])
      if (e) out.push_back(*e);
  }
  report.accepted = out.size();
  return out;
}

}  // namespace lista::align
