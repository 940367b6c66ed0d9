// align_missions: closures between the missions (mission_links.hpp), a
// joint pose graph of every scan (mission_graph.hpp) with scan-to-scan
// edges (scan_edge_check.hpp), solved, refined with closures the solution
// brings near, and checked for scan edges that disagree with the closures.
#include "joint_alignment.hpp"

#include "mission_graph.hpp"
#include "mission_links.hpp"
#include "scan_edge_check.hpp"
#include "station_links.hpp"
#include "stopwatch.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <set>

namespace lista::align {
namespace {

// Solves `g` on the closures, draws them again from the verified ones the
// solution agrees with, and adds closures between keyframes the solution
// brings within refine_radius (o.refine_rounds rounds). Returns the final
// closures; `g` holds the solution.
std::vector<Closure> solve_and_refine(const MissionSet& set, const MissionClosures& found,
                                      const JointAlignmentOptions& o, Context& ctx, JointAlignmentReport& report,
                                      const Stopwatch& clock, Graph& g) {
  const std::vector<Keyframe>& kf = found.keyframes;
  const int threads = ctx.threads();
  std::vector<Closure> closures = found.closures;
  // First solve without the robust loss: the vetted closures start far from
  // their optimum (the drift), where a robust loss would hardly pull.
  PoseGraphOptions plain = o.graph;
  plain.loss = RobustLoss::none;
  const PoseGraphSummary first = solve(g, closure_edges(set, g, kf, closures, o), plain);
  report.initial_cost = first.initial_cost;
  // Closures the vote refused may agree with the solved graph (drift can make
  // early and late closures look inconsistent with each other).
  closures = agreeing(set, g, kf, found.verified, o.consistency);

  std::set<std::pair<size_t, size_t>> closed;
  for (const auto& c : closures) closed.insert({c.reference, c.query});
  for (int round = 0; round < o.refine_rounds; ++round) {
    ctx.throw_if_cancelled();
    // Proximity closures: keyframes now close in the common frame.
    std::vector<Candidate> near;
    std::vector<Eigen::Isometry3d> guesses;
    std::vector<Eigen::Isometry3d> frames;
    for (const auto& k : kf) frames.push_back(frame_in_common(set, g, k));
    for (size_t q = 0; q < kf.size(); ++q) {
      for (size_t a = 0; a < kf[q].mission; ++a) {
        size_t best = kf.size();
        double best_d = o.refine_radius;
        for (size_t r = 0; r < kf.size(); ++r) {
          if (kf[r].mission != a) continue;
          const double d = (frames[r].translation() - frames[q].translation()).norm();
          if (d <= best_d) {
            best_d = d;
            best = r;
          }
        }
        if (best == kf.size() || closed.count({best, q})) continue;
        near.push_back({best, q, 1.0, 0.0});
        guesses.push_back(frames[best].inverse() * frames[q]);
      }
    }
    const std::vector<Closure> proximity = verify_candidates(kf, near, guesses, o.verify, threads);
    for (const auto& c : proximity) closed.insert({c.reference, c.query});
    closures.insert(closures.end(), proximity.begin(), proximity.end());
    report.proximity += proximity.size();
    ctx.info("refine round " + std::to_string(round + 1) + ": " + std::to_string(near.size()) +
             " proximity candidates, " + std::to_string(proximity.size()) + " verified after " + clock.elapsed());
    PoseGraphOptions robust = o.graph;
    const PoseGraphSummary s = solve(g, closure_edges(set, g, kf, closures, o), robust);
    report.final_cost = s.final_cost;
    if (proximity.empty()) break;
  }
  if (o.refine_rounds == 0) {
    PoseGraphOptions robust = o.graph;
    report.final_cost = solve(g, closure_edges(set, g, kf, closures, o), robust).final_cost;
  }
  return closures;
}

// Stations of different missions registered whole (station_links.hpp) on
// the solved graph. Where they link a pair of missions they replace its
// closures, which measure the same thing from coarser submaps; `g` and
// `base` (the graph the scan edges are vetted on) keep them.
void link_stations(const MissionSet& set, const std::vector<Keyframe>& kf, const JointAlignmentOptions& o,
                   Context& ctx, JointAlignmentReport& report, const Stopwatch& clock, std::vector<Closure>& closures,
                   Graph& base, Graph& g) {
  const std::vector<char> stations = station_missions(set);
  if (std::count(stations.begin(), stations.end(), 1) < 2) return;
  PoseGraphEdge closure_like;
  closure_like.sigma_translation = o.closure_sigma_translation;
  closure_like.sigma_rotation = o.closure_sigma_rotation;
  const StationLinks links = station_link_edges(set, g, stations, o.scan_edges, closure_like, ctx.threads(),
                                                [&] { return ctx.cancelled(); });
  ctx.throw_if_cancelled();
  report.station_links_tried = links.tried;
  report.station_links = links.edges.size();
  ctx.info(std::to_string(links.edges.size()) + " of " + std::to_string(links.tried) +
           " whole-scan registrations between stations of different missions accepted after " + clock.elapsed());
  if (links.edges.empty()) return;
  closures.erase(std::remove_if(closures.begin(), closures.end(),
                                [&](const Closure& c) {
                                  const size_t a = kf[c.reference].mission, b = kf[c.query].mission;
                                  return links.pairs.count({std::min(a, b), std::max(a, b)}) > 0;
                                }),
                 closures.end());
  for (Graph* h : {&base, &g}) h->within.insert(h->within.end(), links.edges.begin(), links.edges.end());
  report.final_cost = solve(g, closure_edges(set, g, kf, closures, o), o.graph).final_cost;
}

}  // namespace

MissionSet align_missions(const MissionSet& set, const JointAlignmentOptions& o, Context& ctx,
                          JointAlignmentReport& report) {
  if (set.missions.empty()) throw Error("no missions to align");
  for (const auto& m : set.missions)
    if (m.scans.empty()) throw Error("mission '" + m.name + "' has no scans");
  const size_t n = set.missions.size();
  report = {};
  report.closures_per_mission.assign(n, 0);
  if (n == 1) {
    MissionSet out = set;
    out.missions[0].to_common = Eigen::Isometry3d::Identity();
    return out;
  }
  const Stopwatch clock;
  const MissionClosures found = find_mission_closures(set, o, ctx, report, clock);
  Graph g = odometry_graph(set, initial_transforms(set, found.keyframes, found.closures, report), o);
  Graph vetting_base = g;  // the odometry (and below, station links): what scan edges are vetted on
  ScanEdgeReport scan_report;
  const std::vector<PoseGraphEdge> scan_edges =
      scan_edges_with_notes(set, g.offset, o, ctx, report, scan_report, clock);
  g.within.insert(g.within.end(), scan_edges.begin(), scan_edges.end());
  std::vector<Closure> closures = solve_and_refine(set, found, o, ctx, report, clock, g);
  report.linked = linked_to_first(set.missions.size(), found.keyframes, closures);
  link_stations(set, found.keyframes, o, ctx, report, clock, closures, vetting_base, g);
  report.final_closures = closures.size();
  if (o.check_scan_disagreement && !scan_edges.empty() && !closures.empty())
    vet_scan_edges(set, found.keyframes, closures, scan_edges, scan_report, vetting_base, o, ctx, report, g);
  return with_graph_poses(set, g);
}

}  // namespace lista::align
