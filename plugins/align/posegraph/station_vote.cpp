#include "station_vote.hpp"

#include "seen_through.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <tuple>

namespace lista::align {
namespace {

// The verified placements of one station pair (a < b), each a_T_b.
struct PairPlacements {
  std::vector<GlobalPlacement> placements;
  Eigen::Vector3d centre_b = Eigen::Vector3d::Zero();  // b's map centroid, where placements are compared
};

using PairMap = std::map<std::pair<size_t, size_t>, PairPlacements>;

// x_T_y for every placement of the pair, whichever way round it was searched.
std::vector<Eigen::Isometry3d> transforms(const PairMap& pairs, size_t x, size_t y) {
  std::vector<Eigen::Isometry3d> out;
  const auto it = pairs.find(std::minmax(x, y));
  if (it == pairs.end()) return out;
  for (const auto& p : it->second.placements)
    out.push_back(x < y ? p.reference_T_query : p.reference_T_query.inverse());
  return out;
}

// The pair's best placement (plan-view score) that agrees with x_T_y; none
// when none does.
const GlobalPlacement* agreeing(const PairMap& pairs, size_t x, size_t y, const Eigen::Isometry3d& x_T_y) {
  const auto it = pairs.find(std::minmax(x, y));
  if (it == pairs.end()) return nullptr;
  const Eigen::Isometry3d a_T_b = x < y ? x_T_y : x_T_y.inverse();
  const GlobalPlacement* best = nullptr;
  for (const auto& p : it->second.placements)
    if (same_placement(p.reference_T_query, a_T_b, it->second.centre_b) && (!best || p.plan_score > best->plan_score))
      best = &p;
  return best;
}

double agreeing_score(const PairMap& pairs, size_t x, size_t y, const Eigen::Isometry3d& x_T_y) {
  const GlobalPlacement* p = agreeing(pairs, x, y, x_T_y);
  return p ? p->plan_score : 0.0;
}

// Stations placed in groups, each in the frame of its group's first.
struct Layout {
  std::vector<std::optional<Eigen::Isometry3d>> at;
  std::vector<size_t> group;
  bool placed_together(size_t a, size_t b) const { return at[a] && at[b] && group[a] == group[b]; }
  Eigen::Isometry3d between(size_t a, size_t b) const { return at[a]->inverse() * *at[b]; }
};

// Grown from one pair's placement by adding, each time, the station whose
// placement (some pair's placement from a station already placed) the placed
// stations' pairs agree with most (their plan-view scores summed). Stations
// it does not reach start a group of their own from their best pair.
Layout grow_layout(const PairMap& pairs, const std::vector<size_t>& list, size_t n,
                   const std::pair<size_t, size_t>& seed_pair, const Eigen::Isometry3d& seed) {
  Layout layout;
  layout.at.assign(n, std::nullopt);
  layout.group.assign(n, 0);
  std::optional<std::pair<std::pair<size_t, size_t>, Eigen::Isometry3d>> start{{seed_pair, seed}};
  for (size_t group = 0; start; ++group) {
    const auto [a, b] = start->first;
    layout.at[a] = Eigen::Isometry3d::Identity();
    layout.at[b] = start->second;
    layout.group[a] = layout.group[b] = group;
    for (;;) {
      double best_gain = 0.0;
      std::optional<std::pair<size_t, Eigen::Isometry3d>> best;
      for (size_t c : list) {
        if (layout.at[c]) continue;
        for (size_t p : list) {
          if (!layout.at[p] || layout.group[p] != group) continue;
          for (const auto& p_T_c : transforms(pairs, p, c)) {
            const Eigen::Isometry3d at_c = *layout.at[p] * p_T_c;
            double gain = 0.0;
            for (size_t q : list)
              if (layout.at[q] && layout.group[q] == group)
                gain += agreeing_score(pairs, q, c, layout.at[q]->inverse() * at_c);
            if (gain > best_gain) best_gain = gain, best = {{c, at_c}};
          }
        }
      }
      if (!best) break;
      layout.at[best->first] = best->second;
      layout.group[best->first] = group;
    }
    start.reset();
    double best_score = 0.0;
    for (const auto& [key, pp] : pairs) {
      if (layout.at[key.first] || layout.at[key.second]) continue;
      for (const auto& p : pp.placements)
        if (p.plan_score > best_score) best_score = p.plan_score, start = {{key, p.reference_T_query}};
    }
  }
  return layout;
}

// Which placement each pair keeps under the layout (its index, or -1):
// layouts alike in this are one layout.
std::vector<int> kept_placements(const PairMap& pairs, const Layout& layout) {
  std::vector<int> out;
  for (const auto& [key, pp] : pairs) {
    const GlobalPlacement* p = layout.placed_together(key.first, key.second)
                                   ? agreeing(pairs, key.first, key.second, layout.between(key.first, key.second))
                                   : nullptr;
    out.push_back(p ? int(p - pp.placements.data()) : -1);
  }
  return out;
}

// How much a layout contradicts what the stations saw: for every two
// stations placed together, the shares of each one's points the layout puts
// where the other's sensor saw through (seen_through.hpp), summed.
class LayoutConflicts {
 public:
  LayoutConflicts(const std::vector<Keyframe>& kf, const std::vector<char>& stations) : kf_(kf) {
    for (size_t k = 0; k < kf.size(); ++k)
      if (stations[kf[k].mission]) keyframes_.push_back(k), seen_.emplace_back(kf[k].submap);
  }
  // `shares`, if given, counts the shares summed.
  double of(const Layout& layout, const std::vector<size_t>& list, size_t* shares = nullptr) const {
    double sum = 0.0;
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j) sum += between(layout, list[i], list[j], shares);
    return sum;
  }
  // Those of the pairs station c is in.
  double of_station(const Layout& layout, const std::vector<size_t>& list, size_t c) const {
    double sum = 0.0;
    for (size_t q : list)
      if (q != c) sum += between(layout, q, c);
    return sum;
  }

 private:
  double between(const Layout& layout, size_t a, size_t b, size_t* shares = nullptr) const {
    if (!layout.placed_together(a, b)) return 0.0;
    size_t n = 0;
    const double sum = conflicts_between(kf_, keyframes_, seen_, a, b, layout.between(a, b), n);
    if (shares) *shares += n;
    return sum;
  }
  const std::vector<Keyframe>& kf_;
  std::vector<size_t> keyframes_;  // of the stations
  std::vector<SeenThrough> seen_;
};

// Each station's partners registered until this many verified a placement
// (register_best_partners): enough that a wrong one is outvoted.
constexpr size_t kPartners = 6;

// Layouts are grown from at most this many seeds (the pairs' best
// placements, best first): one right seed grows the right layout.
constexpr size_t kSeeds = 32;

}  // namespace

std::set<std::pair<size_t, size_t>> register_best_partners(
    const std::vector<size_t>& stations, const std::map<std::pair<size_t, size_t>, double>& fits, size_t partners,
    const std::function<bool(const std::pair<size_t, size_t>&)>& register_pair, Progress* progress) {
  std::set<std::pair<size_t, size_t>> registered, verified_pairs;
  for (size_t c : stations) {
    std::vector<std::pair<double, size_t>> ranked;  // (plan-view fit, partner)
    for (size_t p : stations) {
      const auto it = p == c ? fits.end() : fits.find(std::minmax(c, p));
      if (it != fits.end()) ranked.emplace_back(it->second, p);
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    // At most twice `partners` tried: where the best-fitting fail, the
    // station shares too little with the rest for more to help, and trying
    // every one would be every pair again.
    if (ranked.size() > 2 * partners) ranked.resize(2 * partners);
    size_t verified = 0;
    for (const auto& [fit, p] : ranked) {
      if (verified >= partners) break;
      const auto key = std::minmax(c, p);
      if (registered.insert(key).second && register_pair(key)) verified_pairs.insert(key);
      verified += verified_pairs.count(key);
    }
    if (progress) progress->advance();
  }
  return registered;
}

StationVote vote_station_placements(const std::vector<Keyframe>& kf, const std::vector<char>& stations,
                                    const std::vector<Closure>& incumbents, const GlobalSearchOptions& o,
                                    const VerifyOptions& verify, int threads,
                                    const std::function<void()>& throw_if_cancelled, Progress* progress) {
  StationVote vote;
  std::vector<size_t> list;
  for (size_t m = 0; m < stations.size(); ++m)
    if (stations[m]) list.push_back(m);
  if (list.size() < 3) return vote;
  // The closures' own placement of each pair: its tightest closure's.
  std::map<std::pair<size_t, size_t>, std::pair<double, Eigen::Isometry3d>> incumbent;
  for (const Closure& c : incumbents) {
    const size_t r = kf[c.reference].mission, q = kf[c.query].mission;
    if (r == q || !stations[r] || !stations[q]) continue;
    const auto key = std::minmax(r, q);
    const auto it = incumbent.find(key);
    if (it != incumbent.end() && it->second.first <= c.rmse) continue;
    const Eigen::Isometry3d r_T_q = implied_map_transform(kf, c);
    incumbent[key] = {c.rmse, r < q ? r_T_q : r_T_q.inverse()};
  }
  // Every pair's plan views are correlated (cheap); registering the whole
  // maps, most of the time, is kept for each station's best partners.
  MissionMaps maps(kf, o, verify);
  std::map<std::pair<size_t, size_t>, std::vector<GlobalPlacement>> candidates;
  if (progress) progress->begin("plan-view searches between stations", list.size() * (list.size() - 1) / 2);
  for (size_t i = 0; i < list.size(); ++i)
    for (size_t j = i + 1; j < list.size(); ++j) {
      throw_if_cancelled();
      vote.decided.insert({list[i], list[j]});
      candidates[{list[i], list[j]}] = plan_view_placements(maps, list[i], list[j], threads);
      if (progress) progress->advance();
    }
  if (progress) progress->end();
  std::map<std::pair<size_t, size_t>, double> fits;
  for (const auto& [key, found] : candidates)
    if (!found.empty()) fits[key] = found.front().plan_score;
  PairMap pairs;
  if (progress) progress->begin("whole-map registrations between stations", list.size());
  const auto registered = register_best_partners(list, fits, kPartners, [&](const std::pair<size_t, size_t>& key) {
    throw_if_cancelled();
    const auto it = incumbent.find(key);
    PlacementSearch found =
        verified_placements(maps, key.first, key.second, candidates[key], threads,
                            it == incumbent.end() ? std::nullopt : std::optional<Eigen::Isometry3d>(it->second.second));
    found.verified.erase(std::remove_if(found.verified.begin(), found.verified.end(),
                                        [&](const GlobalPlacement& p) { return p.overlap < o.min_overlap; }),
                         found.verified.end());
    if (found.verified.empty()) return false;
    pairs[key] = {std::move(found.verified), found.query_centre};
    return true;
  }, progress);
  if (progress) progress->end();
  vote.registered = registered.size();
  vote.pairs = pairs.size();
  if (pairs.empty()) return vote;
  // Layouts grown from the pairs' best placements; the one that puts the
  // fewest points where another station's sensor saw through, summed over
  // every pair placed together (a pair whose right placement no search
  // verified still counts), wins.
  std::vector<std::tuple<double, std::pair<size_t, size_t>, Eigen::Isometry3d>> seeds;
  for (const auto& [key, pp] : pairs) {
    const GlobalPlacement* top = &pp.placements.front();
    for (const auto& p : pp.placements)
      if (p.plan_score > top->plan_score) top = &p;
    seeds.emplace_back(top->plan_score, key, top->reference_T_query);
  }
  std::stable_sort(seeds.begin(), seeds.end(),
                   [](const auto& x, const auto& y) { return std::get<0>(x) > std::get<0>(y); });
  seeds.resize(std::min(seeds.size(), kSeeds));
  const LayoutConflicts judge(kf, stations);
  std::vector<std::vector<int>> seen;
  std::optional<Layout> best;
  double fewest = 0.0;
  for (const auto& [top, key, placement] : seeds) {
    Layout layout = grow_layout(pairs, list, stations.size(), key, placement);
    std::vector<int> kept = kept_placements(pairs, layout);
    if (std::find(seen.begin(), seen.end(), kept) != seen.end()) continue;
    seen.push_back(std::move(kept));
    const double c = judge.of(layout, list);
    if (!best || c < fewest) fewest = c, best = std::move(layout);
  }
  // Growing favours the best-fitting placements, which a half-turned station
  // can have: each station is then moved to any placement its pairs offer
  // while that lowers the conflicts.
  for (bool moved = true; moved;) {
    moved = false;
    for (size_t c : list) {
      throw_if_cancelled();
      if (!best->at[c]) continue;
      double now = judge.of_station(*best, list, c);
      for (size_t p : list) {
        if (p == c || !best->placed_together(p, c)) continue;
        for (const auto& p_T_c : transforms(pairs, p, c)) {
          Layout trial = *best;
          trial.at[c] = *best->at[p] * p_T_c;
          if (same_placement(*trial.at[c], *best->at[c], Eigen::Vector3d::Zero())) continue;
          const double after = judge.of_station(trial, list, c);
          if (after < now - 1e-9) now = after, best = std::move(trial), moved = true;
        }
      }
    }
  }
  size_t shares = 0;
  const double summed = judge.of(*best, list, &shares);
  vote.conflict = shares ? summed / double(shares) : 0.0;
  // Each pair keeps its best placement that agrees with the layout.
  const std::vector<int> kept = kept_placements(pairs, *best);
  size_t pair = 0;
  for (const auto& [key, pp] : pairs) {
    const int keep = kept[pair++];
    if (keep < 0) continue;
    ++vote.kept;
    const auto closures = placement_closures(kf, key.first, key.second, pp.placements[size_t(keep)], o.max_pairs);
    vote.closures.insert(vote.closures.end(), closures.begin(), closures.end());
  }
  return vote;
}

}  // namespace lista::align
