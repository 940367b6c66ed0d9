#include "scan_edge_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace lista::align {

std::vector<size_t> missions_to_retry_on_maps(const std::vector<char>& had_edges, const std::vector<char>& blamed,
                                              bool all_left_out, const std::vector<bool>& on_maps, bool maps_allowed) {
  std::vector<size_t> retry;
  for (size_t m = 0; maps_allowed && m < had_edges.size(); ++m)
    if (had_edges[m] && (all_left_out || blamed[m]) && !on_maps[m]) retry.push_back(m);
  return retry;
}

std::string scan_edges_warning(const std::string& mission, size_t accepted, size_t tried) {
  if (tried < 8 || 2 * accepted >= tried) return "";
  // Measured on correct poses: a VLP-16 on an open site registers about a
  // third (fsc seeds 2 and 36: 151 and 182 of 494 over both missions); the
  // demo's mission B with its poses shuffled registers 0 of 13.
  return "mission '" + mission + "': only " + std::to_string(accepted) + " of " + std::to_string(tried) +
         " neighbouring scans register where their poses (poses.txt or VIEWPOINT) put them, so the alignment "
         "leans on the odometry and loop closures there. Sparse scans that overlap little do this (a 16-beam "
         "scanner outdoors); otherwise check that there is one pose per scan in file-name order (scan_10.pcd "
         "sorts before scan_2.pcd) and that scans are in the sensor frame";
}

bool scan_edges_disagree(double residual_with, double residual_without, double ratio) {
  // The 1 cm keeps millimetre residuals (a dense scanner indoors) from
  // deciding on noise.
  return residual_with > ratio * residual_without && residual_with > residual_without + 0.01;
}

std::vector<char> missions_to_blame(double residual_with_all, const std::vector<double>& residual_without_each,
                                    double ratio) {
  std::vector<char> blame(residual_without_each.size(), 0);
  if (blame.size() < 3) return blame;  // of two, taking one out leaves the other to judge alone
  for (size_t m = 0; m < blame.size(); ++m)
    blame[m] = !std::isnan(residual_without_each[m]) &&
               scan_edges_disagree(residual_with_all, residual_without_each[m], ratio);
  return blame;
}

std::string unlinked_stations_warning(const Mission& mission, size_t offset, const std::vector<PoseGraphEdge>& edges) {
  std::vector<size_t> held, group(mission.scans.size());
  for (size_t s = 0; s < mission.scans.size(); ++s) {
    group[s] = s;
    if (mission.scans[s].points && !mission.scans[s].points->empty()) held.push_back(s);
  }
  auto root = [&](size_t s) {
    while (group[s] != s) s = group[s] = group[group[s]];
    return s;
  };
  for (const PoseGraphEdge& e : edges)
    if (e.from >= offset && e.to >= offset && e.from - offset < group.size() && e.to - offset < group.size())
      group[root(e.from - offset)] = root(e.to - offset);
  std::set<size_t> parts;
  for (size_t s : held) parts.insert(root(s));
  if (parts.size() <= 1) return "";
  return "mission '" + mission.name + "' (stop-and-go stations): its " + std::to_string(held.size()) +
         " stations fall into " + std::to_string(parts.size()) +
         " groups that no registration links, so they stand where poses.txt puts them; where poses.txt is only "
         "roughly right, so are the changes";
}

std::vector<PoseGraphEdge> scan_edges_with_notes(const MissionSet& set, const std::vector<size_t>& offsets,
                                                 const JointAlignmentOptions& o, Context& ctx,
                                                 JointAlignmentReport& report, ScanEdgeReport& scan_report,
                                                 const Stopwatch& clock) {
  const std::vector<PoseGraphEdge> scan_edges =
      scan_registration_edges(set, offsets, o.scan_edges, ctx.threads(), scan_report,
                              [&] { return ctx.cancelled(); }, [&] { ctx.throw_if_cancelled(); });
  report.scan_edges_tried = scan_report.tried;
  report.scan_edges = scan_report.accepted;
  if (scan_report.tried > 0)
    ctx.info(std::to_string(scan_report.accepted) + " of " + std::to_string(scan_report.tried) +
             " scan-to-scan registrations accepted after " + clock.elapsed());
  for (size_t m = 0; m < scan_report.stations.size(); ++m) {
    if (!scan_report.stations[m]) continue;
    if (const std::string w = unlinked_stations_warning(set.missions[m], offsets[m], scan_edges); !w.empty())
      ctx.warn(w);
    ++report.station_missions;
    ctx.info("mission '" + set.missions[m].name + "': its scans stand farther apart than their points reach " +
             "(stop-and-go stations): a pair is judged on the overlap of whole maps (" +
             std::to_string(int(std::lround(100.0 * o.scan_edges.station_min_overlap))) + " %), not " +
             std::to_string(int(std::lround(100.0 * o.scan_edges.gates.min_overlap))) + " %");
  }
  for (size_t m = 0; m < scan_report.scan_to_map.size(); ++m) {
    if (!scan_report.scan_to_map[m]) continue;
    ++report.scan_map_missions;
    if (scan_report.pairs_tried[m] > 0)
      ctx.info("mission '" + set.missions[m].name + "': " + std::to_string(scan_report.pairs_accepted[m]) + " of " +
               std::to_string(scan_report.pairs_tried[m]) +
               " scan-to-scan registrations accepted, so each scan is registered onto a local map of the " +
               std::to_string(o.scan_edges.map_scans) + " scans before it instead (scans.map_scans): " +
               std::to_string(scan_report.accepted_per_mission[m]) + " of " +
               std::to_string(scan_report.tried_per_mission[m]) + " accepted");
  }
  // Per mission: one mission whose poses are not its scans' hides among
  // well-registered ones in the total.
  for (size_t m = 0; m < scan_report.tried_per_mission.size(); ++m)
    if (const std::string w = scan_edges_warning(set.missions[m].name, scan_report.accepted_per_mission[m],
                                                 scan_report.tried_per_mission[m]);
        !w.empty())
      ctx.warn(w);
  return scan_edges;
}

void vet_scan_edges(const MissionSet& set, const std::vector<Keyframe>& kf, const std::vector<Closure>& closures,
                    const std::vector<PoseGraphEdge>& scan_edges, const ScanEdgeReport& scan_report,
                    const Graph& odometry_only, const JointAlignmentOptions& o, Context& ctx,
                    JointAlignmentReport& report, Graph& g) {
  const size_t n = set.missions.size();
  const int threads = ctx.threads();
  // The odometry plus `edges`, solved on the final closures as align_missions solves.
  auto solved_with = [&](const std::vector<PoseGraphEdge>& edges, double& cost) {
    Graph h = odometry_only;
    h.within.insert(h.within.end(), edges.begin(), edges.end());
    PoseGraphOptions plain = o.graph;
    plain.loss = RobustLoss::none;
    solve(h, closure_edges(set, h, kf, closures, o), plain);
    PoseGraphOptions robust = o.graph;
    cost = solve(h, closure_edges(set, h, kf, closures, o), robust).final_cost;
    return h;
  };
  double cost_without = 0.0;
  Graph without = solved_with({}, cost_without);
  const double with_all = closure_rms(set, g, kf, closures), with_none = closure_rms(set, without, kf, closures);
  report.closure_residual_with_scan_edges = with_all;
  report.closure_residual_without_scan_edges = with_none;
  if (scan_edges_disagree(with_all, with_none, o.scan_disagreement)) {
    // Whose? A mission whose edges, taken out alone, bring the residual
    // down as far (the others' then agree with the closures).
    std::vector<std::vector<PoseGraphEdge>> by_mission(n);
    for (const auto& e : scan_edges) by_mission[mission_of(g, e.from)].push_back(e);
    auto all_but = [&](size_t skip) {
      std::vector<PoseGraphEdge> out;
      for (size_t m = 0; m < n; ++m)
        if (m != skip) out.insert(out.end(), by_mission[m].begin(), by_mission[m].end());
      return out;
    };
    std::vector<double> without_each(n, std::nan(""));
    for (size_t m = 0; m < n && n > 2; ++m) {
      if (by_mission[m].empty()) continue;
      double unused = 0.0;
      without_each[m] = closure_rms(set, solved_with(all_but(m), unused), kf, closures);
    }
    const std::vector<char> culprit = missions_to_blame(with_all, without_each, o.scan_disagreement);
    std::string left;
    size_t with_edges = 0;
    std::vector<char> had_edges(n);
    for (size_t m = 0; m < n; ++m) {
      had_edges[m] = !by_mission[m].empty();
      with_edges += had_edges[m];
      if (!culprit[m]) continue;
      left += (left.empty() ? "'" : ", '") + set.missions[m].name + "'";
      ++report.scan_edges_left_out;
      by_mission[m].clear();
    }
    std::vector<PoseGraphEdge> kept = all_but(n);
    double cost_kept = 0.0;
    Graph with_kept = report.scan_edges_left_out > 0 && !kept.empty() ? solved_with(kept, cost_kept) : Graph{};
    // No mission alone to blame, or the rest still disagrees: all go.
    if (report.scan_edges_left_out == 0 || kept.empty() ||
        scan_edges_disagree(closure_rms(set, with_kept, kf, closures), with_none, o.scan_disagreement)) {
      kept.clear();
      left = "every mission";
      report.scan_edges_left_out = with_edges;
    }
    report.final_cost = kept.empty() ? cost_without : cost_kept;
    g = kept.empty() ? std::move(without) : std::move(with_kept);
    char buf[160];
    std::snprintf(buf, sizeof buf, "(closure residual %.3f m with them, %.3f m without", with_all, with_none);
    std::string residuals = buf;
    // The missions left out that registered scan to scan try local maps
    // instead: a pair of single sparse scans registers ring onto ring,
    // several scans fill the gaps. Kept if they agree with the closures.
    const std::vector<size_t> retry =
        missions_to_retry_on_maps(had_edges, culprit, kept.empty(), scan_report.scan_to_map,
                                  o.scan_edges.map_scans > 1 && o.scan_edges.map_use != MapUse::never);
    bool replaced = false;
    if (!retry.empty()) {
      MissionSet some;
      std::vector<size_t> offsets;
      for (size_t m : retry) {
        some.missions.push_back(set.missions[m]);
        offsets.push_back(g.offset[m]);
      }
      ScanEdgeOptions maps = o.scan_edges;
      maps.map_use = MapUse::always;
      ScanEdgeReport unused_report;
      std::vector<PoseGraphEdge> trial = kept;
      for (const auto& e : scan_registration_edges(some, offsets, maps, threads, unused_report,
                                                   [&] { return ctx.cancelled(); }, [&] { ctx.throw_if_cancelled(); }))
        trial.push_back(e);
      double cost_trial = 0.0;
      Graph with_maps = solved_with(trial, cost_trial);
      const double with_maps_rms = closure_rms(set, with_maps, kf, closures);
      if (trial.size() > kept.size() && !scan_edges_disagree(with_maps_rms, with_none, o.scan_disagreement)) {
        replaced = true;
        g = std::move(with_maps);
        report.final_cost = cost_trial;
        report.scan_edges_left_out -= retry.size();
        report.scan_map_missions += retry.size();
        std::snprintf(buf, sizeof buf, "; %.3f m onto local maps", with_maps_rms);
        residuals += buf;
      }
    }
    residuals += ")";
    if (replaced)
      ctx.info("scan-to-scan registrations disagree with the loop closures " + residuals + ": those of " +
               left + " registered onto local maps of " + std::to_string(o.scan_edges.map_scans) +
               " scans instead (scans.map_scans), which agree");
    else
      ctx.warn("scan-to-scan registrations disagree with the loop closures " + residuals +
               ": those of " + left + " left out, whose poses rest on odometry and closures; a sparse scanner's "
               "rings can bias such registrations (docs/alignment.md)");
  }
}

}  // namespace lista::align
