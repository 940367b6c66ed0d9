#include "mission_links.hpp"

#include "station_links.hpp"
#include "seen_through.hpp"
#include "station_vote.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <map>
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

}  // namespace

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

namespace {

std::string plan_view_note(const GlobalPlacement& p) {
  char text[160];
  std::snprintf(text, sizeof text, "%.0f %% of the plan view lies on the other map under it against %.0f %% under the closures'",
                100.0 * p.plan_score, 100.0 * p.incumbent_plan_score);
  return text;
}

// The whole-map search of a mission pair (global_search.hpp), its choice as
// closures; between two missions scanned from stations what their stations
// saw may overrule the plan view (judge_station_placements), said in `note`.
std::optional<GlobalPlacement> searched_placement(const std::vector<Keyframe>& kf, size_t a, size_t b,
                                                  const std::vector<char>& stations, const JointAlignmentOptions& o,
                                                  Context& ctx, const std::optional<Eigen::Isometry3d>& incumbent,
                                                  std::string& note) {
  const PlacementSearch search = verified_placements(kf, a, b, o.global, o.verify, ctx.threads(), incumbent);
  std::optional<GlobalPlacement> best = plan_view_choice(search, o.global, incumbent);
  note.clear();
  if (stations[a] && stations[b]) {
    StationJudgement judged = judge_station_placements(kf, a, b, search, o.global, incumbent, best);
    if (judged.overruled) best = std::move(judged.choice), note = judged.note;
  }
  if (best) best->closures = placement_closures(kf, a, b, *best, o.global.max_pairs);
  return best;
}

// Mission pairs linked by fewer than check_below closures are checked on
// their whole maps: two or three closures can agree on a half-turned fit of
// a symmetric room. A placement that clearly fits the maps better replaces
// the pair's closures (in `closures` and `verified`), with a warning.
// Returns the pairs (reference, query mission) replaced.
std::vector<std::pair<size_t, size_t>> recheck_weak_links(const MissionSet& set, const std::vector<Keyframe>& kf,
                                                          std::vector<Closure>& closures, std::vector<Closure>& verified,
                                                          const std::set<std::pair<size_t, size_t>>& decided,
                                                          const JointAlignmentOptions& o, Context& ctx) {
  std::map<std::pair<size_t, size_t>, std::vector<size_t>> by_pair;
  for (size_t i = 0; i < closures.size(); ++i) {
    const size_t a = kf[closures[i].reference].mission, b = kf[closures[i].query].mission;
    if (a != b) by_pair[{a, b}].push_back(i);
  }
  std::vector<std::pair<size_t, size_t>> replaced;
  const std::vector<char> stations = station_missions(set);
  for (const auto& [pair, list] : by_pair) {
    if (list.size() >= size_t(std::max(0, o.global.check_below)) || decided.count(std::minmax(pair.first, pair.second)))
      continue;
    ctx.throw_if_cancelled();
    const Closure* tightest = &closures[list.front()];
    for (size_t i : list)
      if (closures[i].rmse < tightest->rmse) tightest = &closures[i];
    const Eigen::Isometry3d incumbent = implied_map_transform(kf, *tightest);
    std::string judged;
    const auto better = searched_placement(kf, pair.first, pair.second, stations, o, ctx, incumbent, judged);
    if (!better) {
      if (!judged.empty())
        ctx.info("'" + set.missions[pair.first].name + "' and '" + set.missions[pair.second].name + "': " + judged);
      continue;
    }
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
                  "from theirs: %s (a near-symmetric place?); check the change maps",
                  list.size(), set.missions[pair.first].name.c_str(), set.missions[pair.second].name.c_str(),
                  rotation_angle(better->reference_T_query.linear().transpose() * incumbent.linear()) * 180.0 / M_PI,
                  judged.empty() ? plan_view_note(*better).c_str() : judged.c_str());
    const auto& unposed = o.unposed_station;
    if (pair.second < unposed.size() && unposed[pair.first] && unposed[pair.second])
      ctx.info(text);
    else
      ctx.warn(text);
  }
  return replaced;
}

// Three or more missions of stations are laid out together
// (station_vote.hpp): the layout's placements replace every station pair's
// closures (in `closures` and `verified`). Returns the pairs it decided.
std::set<std::pair<size_t, size_t>> vote_on_stations(const MissionSet& set, const std::vector<Keyframe>& kf,
                                                     std::vector<Closure>& closures, std::vector<Closure>& verified,
                                                     const JointAlignmentOptions& o, Context& ctx,
                                                     JointAlignmentReport& report) {
  const StationVote vote = vote_station_placements(kf, station_missions(set), closures, o.global, o.verify,
                                                   ctx.threads(), [&] { ctx.throw_if_cancelled(); }, &ctx.progress());
  if (vote.decided.empty()) return {};
  report.station_pairs = vote.pairs;
  report.station_pairs_agreeing = vote.kept;
  report.station_conflict = vote.conflict;
  auto of_decided = [&](const Closure& c) {
    return vote.decided.count(std::minmax(kf[c.reference].mission, kf[c.query].mission)) > 0;
  };
  for (auto* list : {&closures, &verified}) {
    list->erase(std::remove_if(list->begin(), list->end(), of_decided), list->end());
    list->insert(list->end(), vote.closures.begin(), vote.closures.end());
  }
  char text[480];
  std::snprintf(text, sizeof text,
                "stations laid out together: of %zu station pairs, the %zu that fit best by plan view registered, "
                "and the whole-map placements of %zu of the %zu placed agree with the layout; %.1f %% of a "
                "station's points stand where another's sensor saw through",
                vote.decided.size(), vote.registered, vote.kept, vote.pairs, 100.0 * vote.conflict);
  if (layout_is_a_guess(vote))
    ctx.warn(std::string(text) + ": most pairs disagree, so the layout is a guess (stations that see too little "
                                 "of each other?); give registered station poses in poses.txt");
  else
    ctx.info(text);
  return vote.decided;
}

// Each mission the closures leave apart from the first is searched for on
// the maps of the linked missions (global_search.hpp); the best placement
// (highest verified overlap) links it, with a warning, and may in turn place
// others. Returns the closures it found.
std::vector<Closure> link_unplaced_missions(const MissionSet& set, const std::vector<Keyframe>& kf,
                                            const std::vector<Closure>& closures, const JointAlignmentOptions& o,
                                            Context& ctx) {
  const size_t n = set.missions.size();
  const std::vector<char> stations = station_missions(set);
  std::vector<Closure> all = closures, found;
  for (bool progress = true; progress;) {
    progress = false;
    const std::vector<char> linked = linked_to_first(n, kf, all);
    for (size_t m = 1; m < n && !progress; ++m) {
      if (linked[m]) continue;
      ctx.throw_if_cancelled();
      std::optional<GlobalPlacement> best;
      size_t best_on = 0;
      std::string judged, note;
      for (size_t a = 0; a < n; ++a) {
        if (!linked[a]) continue;
        auto p = searched_placement(kf, a, m, stations, o, ctx, std::nullopt, note);
        if (p && (!best || p->overlap > best->overlap)) best = std::move(p), best_on = a, judged = note;
      }
      if (!best) continue;
      char text[480];
      std::snprintf(text, sizeof text,
                    "mission '%s' was placed on '%s' by a whole-map search, since no Scan Context candidate linked it "
                    "(too few scans taken near the same spots?): the maps registered with %.0f %% overlap, inlier "
                    "RMSE %.3f m (%.0f %% of its plan view on the other's); check its change map",
                    set.missions[m].name.c_str(), set.missions[best_on].name.c_str(), 100.0 * best->overlap,
                    best->rmse, 100.0 * best->plan_score);
      ctx.warn(judged.empty() ? std::string(text) : text + ("; " + judged));
      all.insert(all.end(), best->closures.begin(), best->closures.end());
      found.insert(found.end(), best->closures.begin(), best->closures.end());
      progress = true;
    }
  }
  return found;
}

}  // namespace

MissionClosures find_mission_closures(const MissionSet& set, const JointAlignmentOptions& o, Context& ctx,
                                      JointAlignmentReport& report, const Stopwatch& clock) {
  const size_t n = set.missions.size();
  const int threads = ctx.threads();
  std::vector<Keyframe> kf = make_keyframes(set, o.keyframes, threads);
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
           " Scan Context candidates after " + clock.elapsed());
  ctx.throw_if_cancelled();
  std::vector<Closure> verified = verify_candidates(kf, candidates, {}, o.verify, threads);
  report.verified = verified.size();
  std::vector<AmbiguousPlacement> ambiguous;
  std::vector<Closure> closures = consistent_closures(kf, verified, o.consistency, &ambiguous, threads);
  report.consistent = closures.size();
  if (o.global_search) {
    const auto decided = vote_on_stations(set, kf, closures, verified, o, ctx, report);
    const auto replaced = recheck_weak_links(set, kf, closures, verified, decided, o, ctx);
    report.global_replaced = replaced.size();
    // A pair the stations' layout or the whole maps placed is decided,
    // whatever its closures' rival was.
    const auto was_replaced = [&](const AmbiguousPlacement& a) {
      return decided.count(std::minmax(a.reference, a.query)) > 0 ||
             std::find(replaced.begin(), replaced.end(), std::make_pair(a.reference, a.query)) != replaced.end() ||
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
           " consistent after " + clock.elapsed());
  return {std::move(kf), std::move(verified), std::move(closures)};
}

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
  // A station laid out with others (station_vote.hpp) had whole-map
  // placements, which all disagreed with where the others put it.
  const std::vector<char> stations = station_missions(set);
  std::string isolated, detached, outvoted;
  for (size_t m = 0; m < n; ++m) {
    if (to_common[m]) continue;
    std::string& list = report.closures_per_mission[m] != 0                 ? detached
                        : report.station_pairs > 0 && stations[m] ? outvoted
                                                                            : isolated;
    list += (list.empty() ? "'" : ", '") + set.missions[m].name + "'";
  }
  if (!outvoted.empty())
    throw Error("station " + outvoted + " links to no other: of the stations laid out together (" +
                std::to_string(report.station_pairs_agreeing) + " of " + std::to_string(report.station_pairs) +
                " pairs agreeing), none of its whole-map placements agrees with where the others put it (stations that "
                "see too little of each other?); give registered station poses in poses.txt (docs/alignment.md, "
                "\"Stations laid out together\")");
  if (!isolated.empty())
    throw Error("mission " + isolated + " links to no other mission: no verified loop closure (" +
                std::to_string(report.candidates) + " candidates, " + std::to_string(report.verified) +
                " verified in all, and no placement of its whole map verified). Most often the poses do not fit the scans (scans not in the sensor frame, poses in "
                "another order); else the missions do not overlap, or relax candidates.max_descriptor_distance / closures.min_overlap");
  if (!detached.empty())
    throw Error("mission " + detached + " is not connected to the reference mission '" + set.missions[0].name +
                "' by loop closures; every mission must be linked to the reference through overlapping missions");
  std::vector<Eigen::Isometry3d> out;
  for (auto& t : to_common) out.push_back(*t);
  return out;
}

}  // namespace lista::align
