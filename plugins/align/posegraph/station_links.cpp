#include "station_links.hpp"

#include <lista/parallel.hpp>
#include <lista_geometry/stations.hpp>

#include <algorithm>
#include <map>
#include <optional>

namespace lista::align {

std::vector<char> station_missions(const MissionSet& set) {
  std::vector<char> out;
  for (const Mission& m : set.missions) out.push_back(geometry::scanned_from_stations(m));
  return out;
}

StationLinks station_link_edges(const MissionSet& set, const Graph& g, const std::vector<char>& stations,
                                const ScanEdgeOptions& options, const PoseGraphEdge& vertical, int threads,
                                const std::function<bool()>& cancelled) {
  ScanEdgeOptions o = station_edge_options(options);
  o.registration.measure_planes = o.gates.max_plane_rmse > 0.0;
  auto held = [&](size_t m, size_t s) {
    const Scan& scan = set.missions[m].scans[s];
    return scan.points && !scan.points->empty();
  };
  // (earlier mission node, later mission node) pairs, nearest first per station.
  std::vector<std::pair<size_t, size_t>> pairs;
  const size_t nearest = size_t(std::max(1, o.neighbours));
  for (size_t b = 1; b < set.missions.size(); ++b) {
    if (!stations[b]) continue;
    for (size_t a = 0; a < b; ++a) {
      if (!stations[a]) continue;
      for (size_t sb = 0; sb < set.missions[b].scans.size(); ++sb) {
        if (!held(b, sb)) continue;
        const size_t nb = g.offset[b] + sb;
        std::vector<std::pair<double, size_t>> by_distance;
        for (size_t sa = 0; sa < set.missions[a].scans.size(); ++sa) {
          if (!held(a, sa)) continue;
          const size_t na = g.offset[a] + sa;
          const double d = (g.nodes[na].translation() - g.nodes[nb].translation()).norm();
          if (d <= o.max_range) by_distance.push_back({d, na});
        }
        std::sort(by_distance.begin(), by_distance.end());
        for (size_t k = 0; k < std::min(nearest, by_distance.size()); ++k) pairs.push_back({by_distance[k].second, nb});
      }
    }
  }
  StationLinks out;
  out.tried = pairs.size();
  if (pairs.empty()) return out;
  // Each station prepared once, however many pairs it is in.
  std::vector<size_t> used;
  for (const auto& [na, nb] : pairs) used.insert(used.end(), {na, nb});
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  std::vector<PreparedCloud> clouds(used.size());
  parallel_for(used.size(), threads, [&](size_t i) {
    if (cancelled && cancelled()) return;
    const size_t m = mission_of(g, used[i]);
    clouds[i] = PreparedCloud(scan_cloud(set.missions[m].scans[used[i] - g.offset[m]], o), o.registration);
  });
  auto cloud_of = [&](size_t node) -> const PreparedCloud& {
    return clouds[size_t(std::lower_bound(used.begin(), used.end(), node) - used.begin())];
  };
  std::vector<std::optional<PoseGraphEdge>> found(pairs.size());
  parallel_for(pairs.size(), threads, [&](size_t i) {
    if (cancelled && cancelled()) return;
    const auto [na, nb] = pairs[i];
    const Eigen::Isometry3d guess = g.nodes[na].inverse() * g.nodes[nb];
    const auto measured = gated_registration(cloud_of(nb), cloud_of(na), guess, o, true);
    if (!measured) return;
    PoseGraphEdge e = scan_edge(na, nb, *measured, o);
    // Height and level at the closures' sigmas: a sparse scanner's pair
    // registers them less well than x, y and yaw (why scan edges within a
    // mission leave them out), and nothing else ties the two missions in
    // them once these replace the closures.
    e.planar = false;
    e.sigma_height = vertical.sigma_translation;
    e.sigma_tilt = vertical.sigma_rotation;
    found[i] = e;
  });
  for (const auto& e : found)
    if (e) {
      out.edges.push_back(*e);
      out.pairs.insert({mission_of(g, e->from), mission_of(g, e->to)});
    }
  return out;
}

}  // namespace lista::align
