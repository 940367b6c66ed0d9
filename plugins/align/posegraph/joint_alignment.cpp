#include "joint_alignment.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <optional>
#include <set>

namespace lista::align {

namespace {

// Missions reachable from the first through `links` (per mission, the
// missions it is linked to).
std::vector<char> reachable_from_first(const std::vector<std::vector<size_t>>& links) {
  std::vector<char> reached(links.size(), 0);
  if (links.empty()) return reached;
  std::vector<size_t> todo{0};
  reached[0] = 1;
  while (!todo.empty()) {
    const size_t m = todo.back();
    todo.pop_back();
    for (size_t k : links[m])
      if (!reached[k]) reached[k] = 1, todo.push_back(k);
  }
  return reached;
}

// Missions whose placement rests only on ambiguous pairs (a rival fit came
// within the margin): not linked to the first mission through any pair the
// maps decide. With many missions most pairs of a near-symmetric place are
// ambiguous while a few decisive ones pin everything; only the unpinned are
// worth a warning, one each.
std::vector<std::string> unpinned_placements(const MissionSet& set, const std::vector<Keyframe>& kf,
                                             const std::vector<Closure>& closures,
                                             const std::vector<AmbiguousPlacement>& ambiguous) {
  const size_t n = set.missions.size();
  std::set<std::pair<size_t, size_t>> unsure;
  for (const auto& a : ambiguous) unsure.insert(std::minmax(a.reference, a.query));
  std::vector<std::vector<size_t>> decided(n);
  for (const auto& c : closures) {
    const auto pair = std::minmax(kf[c.reference].mission, kf[c.query].mission);
    if (pair.first == pair.second || unsure.count(pair)) continue;
    decided[pair.first].push_back(pair.second);
    decided[pair.second].push_back(pair.first);
  }
  const std::vector<char> pinned = reachable_from_first(decided);
  std::vector<std::string> out;
  for (size_t m = 1; m < n; ++m) {
    if (pinned[m]) continue;
    const AmbiguousPlacement* closest = nullptr;  // the pair whose rival came nearest
    for (const auto& a : ambiguous)
      if ((a.query == m || a.reference == m) &&
          (!closest || a.rival_agreement - a.chosen_agreement > closest->rival_agreement - closest->chosen_agreement))
        closest = &a;
    if (!closest) continue;  // linked only through other unpinned missions: they are named
    char text[512];
    std::snprintf(text, sizeof text,
                  "mission '%s' may be placed wrongly: against '%s' a rival fit turned %.0f deg (%.1f m) from the "
                  "chosen one puts %.1f %% of its points on the other map against %.1f %%, within the margin "
                  "where the closures' vote decides, and no other mission pins it (a near-symmetric place?); "
                  "check the change maps of report.html, or give poses_gt.txt to be told",
                  set.missions[m].name.c_str(),
                  set.missions[closest->query == m ? closest->reference : closest->query].name.c_str(),
                  closest->turn_deg, closest->shift_m, 100.0 * closest->rival_agreement,
                  100.0 * closest->chosen_agreement);
    out.emplace_back(text);
  }
  return out;
}

// Missions linked to the first through inter-mission closures.
std::vector<char> linked_to_first(size_t missions, const std::vector<Keyframe>& kf,
                                  const std::vector<Closure>& closures) {
  std::vector<std::vector<size_t>> links(missions);
  for (const auto& c : closures) {
    const size_t a = kf[c.reference].mission, b = kf[c.query].mission;
    if (a == b) continue;
    links[a].push_back(b);
    links[b].push_back(a);
  }
  return reachable_from_first(links);
}

// Mission pairs linked by fewer than check_below closures are checked on
// their whole maps: two or three closures can agree on a half-turned fit of
// a symmetric room. A placement that clearly fits the maps better replaces
// the pair's closures (in `closures` and `verified`), with a warning.
// Returns the pairs (reference, query mission) replaced.
std::vector<std::pair<size_t, size_t>> recheck_weak_links(const MissionSet& set, const std::vector<Keyframe>& kf, std::vector<Closure>& closures,
                          std::vector<Closure>& verified, const JointAlignmentOptions& o, Context& ctx) {
  std::map<std::pair<size_t, size_t>, std::vector<size_t>> by_pair;
  for (size_t i = 0; i < closures.size(); ++i) {
    const size_t a = kf[closures[i].reference].mission, b = kf[closures[i].query].mission;
    if (a != b) by_pair[{a, b}].push_back(i);
  }
  std::vector<std::pair<size_t, size_t>> replaced;
  for (const auto& [pair, list] : by_pair) {
    if (list.size() >= size_t(std::max(0, o.global.check_below))) continue;
    ctx.throw_if_cancelled();
    const Closure* tightest = &closures[list.front()];
    for (size_t i : list)
      if (closures[i].rmse < tightest->rmse) tightest = &closures[i];
    const Eigen::Isometry3d incumbent = implied_map_transform(kf, *tightest);
    const auto better = global_search(kf, pair.first, pair.second, o.global, o.verify, ctx.threads(), incumbent);
    if (!better) continue;
    auto of_pair = [&](const Closure& c) {
      return kf[c.reference].mission == pair.first && kf[c.query].mission == pair.second;
    };
    closures.erase(std::remove_if(closures.begin(), closures.end(), of_pair), closures.end());
    verified.erase(std::remove_if(verified.begin(), verified.end(), of_pair), verified.end());
    closures.insert(closures.end(), better->closures.begin(), better->closures.end());
    verified.insert(verified.end(), better->closures.begin(), better->closures.end());
    replaced.push_back(pair);
    char text[480];
    std::snprintf(text, sizeof text,
                  "the %zu loop closure(s) between '%s' and '%s' were replaced by a whole-map placement %.0f deg "
                  "from theirs: %.0f %% of the plan view lies on the other map under it against %.0f %% under the "
                  "closures' (a near-symmetric place?); check the change maps",
                  list.size(), set.missions[pair.first].name.c_str(), set.missions[pair.second].name.c_str(),
                  rotation_angle(better->reference_T_query.linear().transpose() * incumbent.linear()) * 180.0 / M_PI,
                  100.0 * better->plan_score, 100.0 * better->incumbent_plan_score);
    ctx.warn(text);
  }
  return replaced;
}

// Each mission the closures leave apart from the first is searched for on
// the maps of the linked missions (global_search.hpp); the best placement
// (highest verified overlap) links it, with a warning, and may in turn place
// others. Returns the closures it found.
std::vector<Closure> link_unplaced_missions(const MissionSet& set, const std::vector<Keyframe>& kf,
                                            const std::vector<Closure>& closures, const JointAlignmentOptions& o,
                                            Context& ctx) {
  const size_t n = set.missions.size();
  std::vector<Closure> all = closures, found;
  for (bool progress = true; progress;) {
    progress = false;
    const std::vector<char> linked = linked_to_first(n, kf, all);
    for (size_t m = 1; m < n && !progress; ++m) {
      if (linked[m]) continue;
      ctx.throw_if_cancelled();
      std::optional<GlobalPlacement> best;
      size_t best_on = 0;
      for (size_t a = 0; a < n; ++a) {
        if (!linked[a]) continue;
        auto p = global_search(kf, a, m, o.global, o.verify, ctx.threads());
        if (p && (!best || p->overlap > best->overlap)) best = std::move(p), best_on = a;
      }
      if (!best) continue;
      char text[480];
      std::snprintf(text, sizeof text,
                    "mission '%s' was placed on '%s' by a whole-map search, since no Scan Context candidate linked it "
                    "(too few scans taken near the same spots?): the maps registered with %.0f %% overlap, inlier "
                    "RMSE %.3f m (%.0f %% of its plan view on the other's); check its change map",
                    set.missions[m].name.c_str(), set.missions[best_on].name.c_str(), 100.0 * best->overlap,
                    best->rmse, 100.0 * best->plan_score);
      ctx.warn(text);
      all.insert(all.end(), best->closures.begin(), best->closures.end());
      found.insert(found.end(), best->closures.begin(), best->closures.end());
      progress = true;
    }
  }
  return found;
}

}  // namespace


namespace {

struct Graph {
  std::vector<size_t> offset;  // first node of each mission
  std::vector<Eigen::Isometry3d> nodes;
  std::vector<bool> fixed;
  std::vector<PoseGraphEdge> within;  // edges inside each mission: odometry and scan-to-scan
};

size_t node_of(const Graph& g, const Keyframe& k) { return g.offset[k.mission] + k.scan; }

// The closure as a relative pose between the two scans' sensor poses.
Eigen::Isometry3d closure_measurement(const MissionSet& set, const std::vector<Keyframe>& kf, const Closure& c) {
  const Keyframe& r = kf[c.reference];
  const Keyframe& q = kf[c.query];
  const auto& pose_r = set.missions[r.mission].scans[r.scan].pose;
  const auto& pose_q = set.missions[q.mission].scans[q.scan].pose;
  return pose_r.inverse() * r.frame * c.reference_T_query * q.frame.inverse() * pose_q;
}

// Keyframe frame in the common frame under the current node estimates.
Eigen::Isometry3d frame_in_common(const MissionSet& set, const Graph& g, const Keyframe& k) {
  return g.nodes[node_of(g, k)] * set.missions[k.mission].scans[k.scan].pose.inverse() * k.frame;
}

// Initial map -> common transforms: a spanning tree over missions from the
// reference, each link the best-fitting closure between the two missions.
std::vector<Eigen::Isometry3d> initial_transforms(const MissionSet& set, const std::vector<Keyframe>& kf,
                                                  const std::vector<Closure>& closures,
                                                  const JointAlignmentReport& report) {
  const size_t n = set.missions.size();
  std::map<std::pair<size_t, size_t>, const Closure*> best;
  for (const auto& c : closures) {
    const auto key = std::make_pair(kf[c.reference].mission, kf[c.query].mission);
    if (key.first == key.second) continue;  // a loop within one mission places nothing
    auto it = best.find(key);
    if (it == best.end() || c.rmse < it->second->rmse) best[key] = &c;
  }
  std::vector<std::optional<Eigen::Isometry3d>> to_common(n);
  to_common[0] = Eigen::Isometry3d::Identity();
  std::deque<size_t> queue{0};
  while (!queue.empty()) {
    const size_t m = queue.front();
    queue.pop_front();
    for (const auto& [pair, c] : best) {
      const Eigen::Isometry3d ref_T_query = implied_map_transform(kf, *c);
      if (pair.first == m && !to_common[pair.second]) {
        to_common[pair.second] = *to_common[m] * ref_T_query;
        queue.push_back(pair.second);
      } else if (pair.second == m && !to_common[pair.first]) {
        to_common[pair.first] = *to_common[m] * ref_T_query.inverse();
        queue.push_back(pair.first);
      }
    }
  }
  std::string isolated, detached;
  for (size_t m = 0; m < n; ++m) {
    if (to_common[m]) continue;
    std::string& list = report.closures_per_mission[m] == 0 ? isolated : detached;
    list += (list.empty() ? "'" : ", '") + set.missions[m].name + "'";
  }
  if (!isolated.empty())
    throw Error("mission " + isolated + " links to no other mission: no verified loop closure (" +
                std::to_string(report.candidates) + " candidates, " + std::to_string(report.verified) +
                " verified in all, and no placement of its whole map verified). Most often the poses do not fit the scans (scans not in the sensor frame, poses in "
                "another order); else the missions do not overlap, or relax max_descriptor_distance / min_overlap");
  if (!detached.empty())
    throw Error("mission " + detached + " is not connected to the reference mission '" + set.missions[0].name +
                "' by loop closures; every mission must be linked to the reference through overlapping missions");
  std::vector<Eigen::Isometry3d> out;
  for (auto& t : to_common) out.push_back(*t);
  return out;
}

std::vector<PoseGraphEdge> closure_edges(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                                         const std::vector<Closure>& closures, const JointAlignmentOptions& o) {
  std::vector<PoseGraphEdge> edges;
  for (const auto& c : closures) {
    PoseGraphEdge e;
    e.from = node_of(g, kf[c.reference]);
    e.to = node_of(g, kf[c.query]);
    e.measurement = closure_measurement(set, kf, c);
    e.sigma_translation = o.closure_sigma_translation;
    e.sigma_rotation = o.closure_sigma_rotation;
    e.robust = true;
    edges.push_back(e);
  }
  return edges;
}

PoseGraphSummary solve(Graph& g, const std::vector<PoseGraphEdge>& closures, PoseGraphOptions options) {
  std::vector<PoseGraphEdge> edges = g.within;
  edges.insert(edges.end(), closures.begin(), closures.end());
  return optimise_pose_graph(g.nodes, g.fixed, edges, options);
}

// Verified closures whose measurement the current estimate agrees with.
std::vector<Closure> agreeing(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                              const std::vector<Closure>& closures, const ConsistencyOptions& o) {
  std::vector<Closure> out;
  for (const auto& c : closures) {
    const Eigen::Isometry3d est = g.nodes[node_of(g, kf[c.reference])].inverse() * g.nodes[node_of(g, kf[c.query])];
    const Eigen::Isometry3d err = closure_measurement(set, kf, c).inverse() * est;
    if (err.translation().norm() <= o.distance / 4 &&
        rotation_angle(err.linear()) <= o.angle / 2)
      out.push_back(c);
  }
  return out;
}

// Root mean square of the closures' translation residuals (m) under the
// graph's current estimate.
double closure_rms(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                   const std::vector<Closure>& closures) {
  if (closures.empty()) return 0.0;
  double sum = 0.0;
  for (const auto& c : closures) {
    const Eigen::Isometry3d est = g.nodes[node_of(g, kf[c.reference])].inverse() * g.nodes[node_of(g, kf[c.query])];
    sum += (closure_measurement(set, kf, c).inverse() * est).translation().squaredNorm();
  }
  return std::sqrt(sum / static_cast<double>(closures.size()));
}

}  // namespace

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
  return ratio > 0.0 && residual_with > ratio * residual_without && residual_with > residual_without + 0.01;
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

MissionSet align_missions(const MissionSet& set, const JointAlignmentOptions& o, Context& ctx,
                          JointAlignmentReport& report) {
  if (set.missions.empty()) throw Error("no missions to align");
  for (const auto& m : set.missions)
    if (m.scans.empty()) throw Error("mission '" + m.name + "' has no scans");
  MissionSet out = set;  // scans' point data is shared, not copied
  const size_t n = set.missions.size();
  report = {};
  report.closures_per_mission.assign(n, 0);
  if (n == 1) {
    out.missions[0].to_common = Eigen::Isometry3d::Identity();
    return out;
  }
  const int threads = ctx.threads();
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&start] {
    return std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()) + " s";
  };

  const std::vector<Keyframe> kf = make_keyframes(set, o.keyframes, threads);
  report.keyframes = kf.size();
  report.submap_distance = kf.empty() ? o.keyframes.submap_distance : kf.front().submap_distance;
  if (report.submap_distance > o.keyframes.submap_distance + 1e-9) {
    char text[200];
    std::snprintf(text, sizeof text,
                  "keyframe submaps grown to %.1f m of path either side: at %.1f m the median one held under %zu "
                  "points (sparse scans)",
                  report.submap_distance, o.keyframes.submap_distance, o.keyframes.submap_min_points);
    ctx.info(text);
  }
  ctx.throw_if_cancelled();
  const std::vector<Candidate> candidates = find_candidates(kf, n, o.candidates, threads);
  report.candidates = candidates.size();
  ctx.info(std::to_string(kf.size()) + " keyframes, " + std::to_string(candidates.size()) +
           " Scan Context candidates after " + elapsed());
  ctx.throw_if_cancelled();
  std::vector<Closure> verified = verify_candidates(kf, candidates, {}, o.verify, threads);
  report.verified = verified.size();
  std::vector<AmbiguousPlacement> ambiguous;
  std::vector<Closure> closures = consistent_closures(kf, verified, o.consistency, &ambiguous);
  report.consistent = closures.size();
  if (o.global_search) {
    const auto replaced = recheck_weak_links(set, kf, closures, verified, o, ctx);
    report.global_replaced = replaced.size();
    // A pair the whole maps placed is decided, whatever its closures' rival was.
    const auto was_replaced = [&](const AmbiguousPlacement& a) {
      return std::find(replaced.begin(), replaced.end(), std::make_pair(a.reference, a.query)) != replaced.end() ||
             std::find(replaced.begin(), replaced.end(), std::make_pair(a.query, a.reference)) != replaced.end();
    };
    ambiguous.erase(std::remove_if(ambiguous.begin(), ambiguous.end(), was_replaced), ambiguous.end());
    const std::vector<Closure> found = link_unplaced_missions(set, kf, closures, o, ctx);
    report.global = found.size();
    // Among the verified too: after the first solve the closures are drawn
    // again from those the solution agrees with.
    verified.insert(verified.end(), found.begin(), found.end());
    closures.insert(closures.end(), found.begin(), found.end());
  }
  // Warned only now, so a pair the whole-map search replaced or a mission it
  // linked is not called unsure on the closures' word.
  for (const std::string& w : unpinned_placements(set, kf, closures, ambiguous)) ctx.warn(w);
  for (const auto& c : closures) {
    if (kf[c.reference].mission == kf[c.query].mission) {
      ++report.intra;
      continue;
    }
    ++report.closures_per_mission[kf[c.reference].mission];
    ++report.closures_per_mission[kf[c.query].mission];
  }
  ctx.info(std::to_string(verified.size()) + " closures verified, " + std::to_string(closures.size()) +
           " consistent after " + elapsed());
  const std::vector<Eigen::Isometry3d> to_common = initial_transforms(set, kf, closures, report);

  Graph g;
  for (size_t m = 0; m < n; ++m) {
    const Mission& mission = set.missions[m];
    g.offset.push_back(g.nodes.size());
    for (size_t s = 0; s < mission.scans.size(); ++s) {
      g.nodes.push_back(to_common[m] * mission.scans[s].pose);
      g.fixed.push_back(m == 0 && (o.fix_reference_mission || s == 0));
      if (s == 0) continue;
      PoseGraphEdge e;
      e.from = g.offset[m] + s - 1;
      e.to = g.offset[m] + s;
      e.measurement = mission.scans[s - 1].pose.inverse() * mission.scans[s].pose;
      e.sigma_translation = o.odometry_sigma_translation;
      e.sigma_rotation = o.odometry_sigma_rotation;
      g.within.push_back(e);
    }
  }
  const Graph odometry_only = g;  // before scan edges and solves
  ScanEdgeReport scan_report;
  const std::vector<PoseGraphEdge> scan_edges = scan_registration_edges(
      set, g.offset, o.scan_edges, threads, scan_report, [&] { return ctx.cancelled(); }, [&] { ctx.throw_if_cancelled(); });
  g.within.insert(g.within.end(), scan_edges.begin(), scan_edges.end());
  report.scan_edges_tried = scan_report.tried;
  report.scan_edges = scan_report.accepted;
  if (scan_report.tried > 0)
    ctx.info(std::to_string(scan_report.accepted) + " of " + std::to_string(scan_report.tried) +
             " scan-to-scan registrations accepted after " + elapsed());
  for (size_t m = 0; m < scan_report.scan_to_map.size(); ++m) {
    if (!scan_report.scan_to_map[m]) continue;
    ++report.scan_map_missions;
    if (scan_report.pairs_tried[m] > 0)
      ctx.info("mission '" + set.missions[m].name + "': " + std::to_string(scan_report.pairs_accepted[m]) + " of " +
               std::to_string(scan_report.pairs_tried[m]) +
               " scan-to-scan registrations accepted, so each scan is registered onto a local map of the " +
               std::to_string(o.scan_edges.map_scans) + " scans before it instead (scan_map): " +
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

  // First solve without the robust loss: the vetted closures start far from
  // their optimum (the drift), where a robust loss would hardly pull.
  PoseGraphOptions plain = o.graph;
  plain.loss = "none";
  plain.threads = threads;
  const PoseGraphSummary first = solve(g, closure_edges(set, g, kf, closures, o), plain);
  report.initial_cost = first.initial_cost;
  // Closures the vote refused may agree with the solved graph (drift can make
  // early and late closures look inconsistent with each other).
  closures = agreeing(set, g, kf, verified, o.consistency);

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
    const std::vector<Closure> found = verify_candidates(kf, near, guesses, o.verify, threads);
    for (const auto& c : found) closed.insert({c.reference, c.query});
    closures.insert(closures.end(), found.begin(), found.end());
    report.proximity += found.size();
    ctx.info("refine round " + std::to_string(round + 1) + ": " + std::to_string(near.size()) +
             " proximity candidates, " + std::to_string(found.size()) + " verified after " + elapsed());
    PoseGraphOptions robust = o.graph;
    robust.threads = threads;
    const PoseGraphSummary s = solve(g, closure_edges(set, g, kf, closures, o), robust);
    report.final_cost = s.final_cost;
    if (found.empty()) break;
  }
  if (o.refine_rounds == 0) {
    PoseGraphOptions robust = o.graph;
    robust.threads = threads;
    report.final_cost = solve(g, closure_edges(set, g, kf, closures, o), robust).final_cost;
  }
  report.final_closures = closures.size();
  // Scan-to-scan edges are tight (millimetres) and outnumber the closures:
  // were they biased (a sparse scanner's rings register ring onto ring,
  // not surface onto surface), the graph would bend the verified closures
  // to fit them. Solved again without them, on the same closures: if they
  // raise the closures' residual several-fold, they are left out: with
  // three or more missions only those of a mission whose removal alone
  // brings the residual down as far (one sparsely scanned mission among
  // dense ones leaves the others their edges), else all.
  if (o.scan_disagreement > 0.0 && !scan_edges.empty() && !closures.empty()) {
    // The odometry plus `edges`, solved on the final closures as above.
    auto solved_with = [&](const std::vector<PoseGraphEdge>& edges, double& cost) {
      Graph h = odometry_only;
      h.within.insert(h.within.end(), edges.begin(), edges.end());
      PoseGraphOptions plain = o.graph;
      plain.loss = "none";
      plain.threads = threads;
      solve(h, closure_edges(set, h, kf, closures, o), plain);
      PoseGraphOptions robust = o.graph;
      robust.threads = threads;
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
      for (const auto& e : scan_edges)
        by_mission[size_t(std::upper_bound(g.offset.begin(), g.offset.end(), e.from) - g.offset.begin()) - 1]
            .push_back(e);
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
                 " scans instead (scan_map), which agree");
      else
        ctx.warn("scan-to-scan registrations disagree with the loop closures " + residuals +
                 ": those of " + left + " left out, whose poses rest on odometry and closures; a sparse scanner's "
                 "rings can bias such registrations (docs/alignment.md)");
    }
  }

  // Each mission keeps its own map frame up to one rigid transform: anchored
  // at its first scan, the rest of the correction goes into the scan poses.
  for (size_t m = 0; m < n; ++m) {
    Mission& mission = out.missions[m];
    const Eigen::Isometry3d tc =
        m == 0 ? Eigen::Isometry3d::Identity() : g.nodes[g.offset[m]] * set.missions[m].scans[0].pose.inverse();
    mission.to_common = tc;
    const Eigen::Isometry3d tc_inv = tc.inverse();
    for (size_t s = 0; s < mission.scans.size(); ++s) mission.scans[s].pose = tc_inv * g.nodes[g.offset[m] + s];
  }
  return out;
}

}  // namespace lista::align
