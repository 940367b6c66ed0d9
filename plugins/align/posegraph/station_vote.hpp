// Placing three or more stations together. A station's map is rigid (one
// scan, or stations with poses), so placements compose exactly: a_T_c *
// c_T_b must be a_T_b. Trusting each pair's own fit fails where it matters
// most: between single scans taken metres apart Scan Context pairs the wrong
// places, and a near-symmetric hall fits a half-turned map about as well as
// the right one. The verified whole-map placements (global_search.hpp) of
// each station's best-fitting partners (by plan view) are kept instead,
// and the stations are laid out where the pairs agree most: grown from a
// pair's placement, station by station, each placed where the placed
// stations' pairs' placements agree with it (their plan-view scores
// summed); of the layouts grown from the pairs' best placements, the one
// that contradicts least what the stations saw wins. Each pair keeps only a
// placement that agrees with it. A symmetric hall's half-turned placements agree among
// themselves as well as the right ones do; what stands in the hall (the
// plan-view score) tells the layouts apart. Internal to align.posegraph
// (docs/alignment.md, "Stations").
#pragma once

#include "global_search.hpp"

#include <lista/context.hpp>
#include <lista/missions.hpp>

#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace lista::align {

struct StationVote {
  std::set<std::pair<size_t, size_t>> decided;  // station pairs (lower mission first) the vote placed or dropped
  std::vector<Closure> closures;                // the kept placements as closures
  size_t registered = 0;                        // station pairs whose whole maps were registered
  size_t pairs = 0;                             // of them, those with a verified placement
  size_t kept = 0;                              // of them, those that agree with the layout
  double conflict = 0.0;  // the layout's mean share of a station's points where another's sensor saw through
};

// Nothing (empty `decided`) with fewer than three stations: no triangles.
// `incumbents` are the closures already found; each pair's best-fitting one
// competes as one more placement. `throw_if_cancelled` is called between
// pairs and moves; `progress`, if given, counts the pairs searched.
StationVote vote_station_placements(const std::vector<Keyframe>& keyframes, const std::vector<char>& stations,
                                    const std::vector<Closure>& incumbents, const GlobalSearchOptions& options,
                                    const VerifyOptions& verify, int threads,
                                    const std::function<void()>& throw_if_cancelled, Progress* progress = nullptr);

// Which station pairs to register on their whole maps: each station's
// partners, best plan-view fit first (`fits`, lower mission first; a pair
// without one has no candidate), until `partners` of them verified a
// placement or twice that many were tried (`register_pair` registers one
// pair and says whether it did).
// Stations far apart share nothing to register, and one that shares much
// with many needs only a few of them. Returns the pairs registered;
// `progress`, if given, counts the stations.
std::set<std::pair<size_t, size_t>> register_best_partners(
    const std::vector<size_t>& stations, const std::map<std::pair<size_t, size_t>, double>& fits, size_t partners,
    const std::function<bool(const std::pair<size_t, size_t>&)>& register_pair, Progress* progress = nullptr);

// Right placements agree with each other: where fewer than half of the
// pairs' do, the stations share too little to be placed by their scans.
inline bool layout_is_a_guess(const StationVote& vote) { return 2 * vote.kept < vote.pairs; }

}  // namespace lista::align
