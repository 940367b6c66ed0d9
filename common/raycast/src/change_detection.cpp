#include <lista_raycast/change_detection.hpp>

#include <lista/parallel.hpp>
#include <lista_geometry/stations.hpp>
#include <lista_geometry/voxel_key.hpp>
#include <lista_raycast/misfit.hpp>
#include <lista_raycast/seen_through.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <omp.h>

namespace lista::raycast {

PairThresholds pair_thresholds(const MissionSet& missions, const VolumetricConfig& c) {
  // Most extreme P a mission of n scans can give a voxel (n updates at most).
  auto most = [&](size_t n) { return std::min(c.clamping_max, probability(float(n) * logodds(c.prob_hit))); };
  auto least = [&](size_t n) { return std::max(c.clamping_min, probability(float(n) * logodds(c.prob_miss))); };
  PairThresholds out;
  for (size_t m = 0; m + 1 < missions.missions.size(); ++m) {
    const Mission &a = missions.missions[m], &b = missions.missions[m + 1];
    const size_t na = a.scans.size(), nb = b.scans.size();
    const double best = std::max(most(na) - least(nb), most(nb) - least(na));
    out.value.push_back(c.change_threshold);
    if (best > c.change_threshold) continue;
    char text[480];
    if (c.change_threshold_given) {
      std::snprintf(text, sizeof text,
                    "missions '%s' (%zu scan%s) and '%s' (%zu scan%s) can show no change: each scan updates a voxel "
                    "at most once, so their probabilities differ by at most %.2f, not above change_threshold %.2f; "
                    "leave change_threshold unset to take the strongest evidence they can give as change",
                    a.name.c_str(), na, na == 1 ? "" : "s", b.name.c_str(), nb, nb == 1 ? "" : "s", best,
                    c.change_threshold);
      out.warnings.emplace_back(text);
      continue;
    }
    // Only the strongest evidence the two can give passes: every scan of one
    // saw the voxel occupied and every scan of the other saw it free (one
    // scan each: one hit against one miss, nothing else observed it).
    out.value.back() = best - kStrongestEvidenceSlack;
    std::snprintf(text, sizeof text,
                  "missions '%s' (%zu scan%s) and '%s' (%zu scan%s) are too few scans for change_threshold %.2f: "
                  "a voxel every scan of one saw occupied and every scan of the other saw free is change "
                  "between them (threshold %.2f; set change_threshold to insist on %.2f)",
                  a.name.c_str(), na, na == 1 ? "" : "s", b.name.c_str(), nb, nb == 1 ? "" : "s", c.change_threshold,
                  out.value.back(), c.change_threshold);
    out.notes.emplace_back(text);
  }
  return out;
}

namespace {

// The neighbourhood (voxels) a pair of missions is judged with: `overall`
// (pair_neighbourhood of the pair's misfit), wider in the regions whose
// own misfit needs more.
struct PairReach {
  int overall = 0;
  std::map<Region, int> wider;
  double region_size = 0.0;  // m, the side of `wider`'s squares
  int at(const Eigen::Vector3d& p, const VolumetricConfig& config) const {
    if (wider.empty()) return overall;
    const auto it = wider.find(region_of(p, config, region_size));
    return it == wider.end() ? overall : it->second;
  }
};

struct Decider {
  const VolumetricConfig& c;
  float occupied_logodds;
  double threshold_previous, threshold_next;  // change_threshold of each pair (pair_thresholds)
  bool one_look_previous, one_look_next;  // both missions of the pair are stations (one_look_pair)
  float hit_once, miss_once;              // log-odds of one hit, of one miss
  PairReach reach_previous, reach_next;   // neighbourhood of each pair

  // True if no voxel within r of v is occupied in `other`.
  bool clear_around(OccupancyReader& other, const Voxel& v, int r) const {
    float l;
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx)
          if (other.logodds(Voxel(v.x() + dx, v.y() + dy, v.z() + dz), l) && l > occupied_logodds)
            return false;
    return true;
  }

  // True if `other` saw free the space one or two voxels behind point p
  // (index units) along its beam from `origin`: the miss went through
  // where the point's surface stood, not past it. Where the beam runs on
  // into a surface the other mission holds (the floor under an object's
  // foot), the space level with the point is asked instead.
  bool seen_behind(OccupancyReader& other, const Voxel& v, const Eigen::Vector3d& p,
                   const Eigen::Vector3d& origin) const {
    const Eigen::Vector3d beam = (p - origin).normalized();
    const Eigen::Vector3d level = Eigen::Vector3d(beam.x(), beam.y(), 0.0).normalized();
    float l_other;
    bool into_static = false;
    for (double depth : {1.0, 2.0}) {
      const Voxel w = voxel_of(p + depth * beam);
      if (w == v || !other.logodds(w, l_other)) continue;
      if (l_other < 0.f) return true;
      into_static = into_static || l_other > occupied_logodds;
    }
    if (!into_static || !level.allFinite()) return false;
    for (double depth : {1.0, 2.0}) {
      const Voxel w = voxel_of(p + depth * level);
      if (w != v && other.logodds(w, l_other) && l_other < 0.f) return true;
    }
    return false;
  }

  // What voxel v alone decides, the same for every point in it: the pairs
  // (ChangedAgainst bits) against which v may be change, and which of them
  // rest on one look each. No bit: no point of v is changed.
  struct VoxelVerdict {
    uint8_t open = 0, looked_once = 0;
  };
  VoxelVerdict at_voxel(OccupancyReader& own, OccupancyReader* previous, OccupancyReader* next,
                        const Voxel& v) const {
    VoxelVerdict verdict;
    float l_own;
    if (!own.logodds(v, l_own) || l_own <= occupied_logodds) return verdict;
    const double p_own = probability(l_own);
    auto against = [&](OccupancyReader* other, double threshold, bool one_look, uint8_t bit) {
      float l_other;
      if (!other || !other->logodds(v, l_other)) return;  // unobserved there: unknown, not change
      const bool looked_once = std::abs(l_own - hit_once) < 1e-4f && std::abs(l_other - miss_once) < 1e-4f;
      if (p_own - probability(l_other) <= threshold && !(one_look && looked_once)) return;
      verdict.open |= bit;
      if (looked_once) verdict.looked_once |= bit;
    };
    against(previous, threshold_previous, one_look_previous, changed_against_previous);
    against(next, threshold_next, one_look_next, changed_against_next);
    return verdict;
  }

  // The ChangedAgainst bits of point p (index units; its voxel v, its
  // scan's sensor at `origin`) of the own map against the previous and the
  // next mission's (either may be null), where at_voxel left pairs open;
  // 0 = not changed.
  uint8_t changed(const VoxelVerdict& verdict, OccupancyReader& own, OccupancyReader* previous, OccupancyReader* next,
                  const Voxel& v, const Eigen::Vector3d& p, const Eigen::Vector3d& origin) const {
    auto against = [&](OccupancyReader* other, const PairReach& reach, uint8_t bit) {
      if (!(verdict.open & bit)) return false;
      // One hit against one miss, however it passed: the miss must have
      // gone through the surface.
      if ((verdict.looked_once & bit) && !seen_behind(*other, v, p, origin)) return false;
      return clear_around(*other, v, reach.at(p, c));
    };
    const uint8_t bits =
        uint8_t((against(previous, reach_previous, changed_against_previous) ? changed_against_previous : 0) |
                (against(next, reach_next, changed_against_next) ? changed_against_next : 0));
    return bits && own.seen_free(v) ? uint8_t(bits | seen_free_in_own_mission) : bits;
  }
};

// Per scan, per point: the ChangedAgainst bits found so far (0 = not changed).
using PointBits = std::vector<std::vector<uint8_t>>;

PointBits no_bits(const Mission& mission) {
  PointBits bits(mission.scans.size());
  for (size_t i = 0; i < bits.size(); ++i) bits[i].assign(mission.scans[i].points->size(), 0);
  return bits;
}

}  // namespace

double one_look_share(const Mission& mission, const OccupancyMap& map, const VolumetricConfig& config) {
  const double inv_res = 1.0 / config.resolution;
  const float hit_once = logodds(config.prob_hit);
  auto reader = map.reader();
  size_t once = 0, all = 0;
  for (size_t i = 0; i < mission.scans.size(); ++i) {
    const PointSet& pts = *mission.scans[i].points;
    const Eigen::Affine3d to_index = Eigen::Scaling(inv_res) * mission.sensor_to_common(i);
    float l;
    for (size_t j = 0; j < pts.size(); j += 16, ++all)
      once += reader->logodds(voxel_of(to_index * pts.xyz[j].cast<double>()), l) && std::abs(l - hit_once) < 1e-4f;
  }
  return all ? double(once) / double(all) : 0.0;
}

namespace {

// Per mission: scanned from stations (lista_geometry/stations.hpp), once.
std::vector<char> stations_of(const MissionSet& missions) {
  std::vector<char> out;
  for (const Mission& m : missions.missions) out.push_back(geometry::scanned_from_stations(m));
  return out;
}

// How each mission was looked at: its one_look_share (filled as its map is
// built) and whether it was scanned from stations.
struct Looks {
  std::vector<double> share;
  std::vector<char> stations;
  explicit Looks(const MissionSet& missions) : share(missions.missions.size(), 0.0), stations(stations_of(missions)) {}
};

// Both missions scanned from stations whose points mostly got one look, and
// no change_threshold given: one hit against one miss is evidence.
bool one_look_pair(const Looks& looks, const VolumetricConfig& config, size_t a, size_t b) {
  return !config.change_threshold_given && looks.stations[a] && looks.stations[b] &&
         looks.share[a] > kStationShare && looks.share[b] > kStationShare;
}

// ORs into `bits` what mission m (map `own_map`) changed against
// `previous_map` and / or `next_map` (either may be null).
void mark_changes(const MissionSet& missions, size_t m, const OccupancyMap& own_map,
                  const OccupancyMap* previous_map, const OccupancyMap* next_map, const VolumetricConfig& config,
                  const PairThresholds& thresholds, const Looks& looks, const std::vector<PairReach>& reach, int threads,
                  PointBits& bits) {
  const Mission& mission = missions.missions[m];
  const Decider decide{config, logodds(config.occupied_threshold),
                       m > 0 ? thresholds.value[m - 1] : config.change_threshold,
                       m < thresholds.value.size() ? thresholds.value[m] : config.change_threshold,
                       m > 0 && one_look_pair(looks, config, m - 1, m),
                       m + 1 < missions.missions.size() && one_look_pair(looks, config, m, m + 1),
                       logodds(config.prob_hit), logodds(config.prob_miss),
                       m > 0 ? reach[m - 1] : PairReach{config.neighbourhood, {}, 0.0},
                       m < reach.size() ? reach[m] : PairReach{config.neighbourhood, {}, 0.0}};
  const double inv_res = 1.0 / config.resolution;
#pragma omp parallel num_threads(std::max(1, threads))
  {
    auto own = own_map.reader();
    std::unique_ptr<OccupancyReader> previous = previous_map ? previous_map->reader() : nullptr;
    std::unique_ptr<OccupancyReader> next = next_map ? next_map->reader() : nullptr;
#pragma omp for schedule(dynamic, 1)
    for (long i = 0; i < static_cast<long>(mission.scans.size()); ++i) {
      const PointSet& pts = *mission.scans[i].points;
      const Eigen::Affine3d to_index = Eigen::Scaling(inv_res) * mission.sensor_to_common(static_cast<size_t>(i));
      const Eigen::Vector3d origin = to_index.translation();
      std::vector<uint8_t>& b = bits[static_cast<size_t>(i)];
      // Neighbouring returns often share a voxel: its verdict is asked once.
      Voxel last(std::numeric_limits<int>::min(), 0, 0);
      Decider::VoxelVerdict verdict;
      for (size_t j = 0; j < pts.size(); ++j) {
        const Eigen::Vector3d p = to_index * pts.xyz[j].cast<double>();
        const Voxel v = voxel_of(p);
        if (v != last) verdict = decide.at_voxel(*own, previous.get(), next.get(), v), last = v;
        if (verdict.open) b[j] |= decide.changed(verdict, *own, previous.get(), next.get(), v, p, origin);
      }
    }
  }
}

// The changed points (bits != 0) in the common frame, in scan then file
// order, with their bits; the number of distinct changed voxels in `voxels`.
PointSet collect_changes(const Mission& mission, const PointBits& bits, double resolution, uint64_t& voxels) {
  const double inv_res = 1.0 / resolution;
  size_t total = 0;
  for (const auto& b : bits) total += static_cast<size_t>(std::count_if(b.begin(), b.end(), [](uint8_t x) { return x; }));
  PointSet set;
  set.reserve(total);
  std::vector<uint8_t> against;  // the scans have no such channel: set after the points
  against.reserve(total);
  std::vector<uint64_t> keys;
  keys.reserve(total);
  for (size_t i = 0; i < mission.scans.size(); ++i) {
    const PointSet& pts = *mission.scans[i].points;
    const Eigen::Isometry3f to_common = mission.sensor_to_common(i).cast<float>();
    const Eigen::Affine3d to_index = Eigen::Scaling(inv_res) * mission.sensor_to_common(i);
    for (size_t j = 0; j < pts.size(); ++j) {
      if (!bits[i][j]) continue;
      set.push_back_from(pts, j);
      against.push_back(bits[i][j]);
      keys.push_back(geometry::voxel_key(voxel_of(to_index * pts.xyz[j].cast<double>())));
      set.xyz.back() = to_common * pts.xyz[j];
      set.scan.back() = static_cast<uint32_t>(i);  // provenance follows the mission's scan order
      if (pts.index.empty()) set.index.back() = static_cast<uint32_t>(j);
    }
  }
  set.changed_against = std::move(against);
  std::sort(keys.begin(), keys.end());
  voxels = static_cast<uint64_t>(std::unique(keys.begin(), keys.end()) - keys.begin());
  return set;
}

// Mission m's changed points (`bits`), its dynamics from the beams near
// them marked, added to `out` and counted in `stats`.
void add_mission(MissionPoints& out, ChangeStats* stats, const MissionSet& missions, size_t m, const PointBits& bits,
                 const VolumetricConfig& config, int threads) {
  const Mission& mission = missions.missions[m];
  uint64_t voxels = 0;
  PointSet set = collect_changes(mission, bits, config.resolution, voxels);
  mark_seen_through(mission, set, config, threads);
  if (stats) {
    stats->changed_points[m] = set.size();
    stats->changed_voxels[m] = voxels;
    stats->seen_free_points[m] = set.seen_free_count();
  }
  out.missions.push_back(mission.name);
  out.sets.push_back(std::move(set));
}

// The pairs taken as stations, in ChangeStats: the share of each mission,
// and a note for each pair the one-look rule applies to (one-scan pairs
// have pair_thresholds' note already).
void note_stations(const MissionSet& missions, const Looks& looks, const VolumetricConfig& config,
                   const PairThresholds& thresholds, ChangeStats* stats) {
  if (!stats) return;
  stats->one_look_share = looks.share;
  const auto& shares = looks.share;
  for (size_t m = 0; m + 1 < shares.size(); ++m) {
    const bool lowered = thresholds.value[m] < config.change_threshold;  // pair_thresholds said so already
    if (!one_look_pair(looks, config, m, m + 1) || lowered) continue;
    char text[400];
    std::snprintf(text, sizeof text,
                  "missions '%s' and '%s' were scanned from stations (%.0f %% and %.0f %% of their points lie in "
                  "voxels one scan saw): a voxel one scan of each saw, occupied against free, is change where the "
                  "free look went through the surface",
                  missions.missions[m].name.c_str(), missions.missions[m + 1].name.c_str(), 100.0 * shares[m],
                  100.0 * shares[m + 1]);
    stats->notes.emplace_back(text);
  }
}

// Of the regions `off`, those in groups of four or more neighbouring ones
// (8-connected). A misfit spans more than a thing does: one or two alone
// are as likely a thing moved by a few centimetres (a barrel turned on its
// spot, a cabinet nudged) that fills their walls, which is change.
template <class Value>
std::vector<Region> in_groups(const std::map<Region, Value>& off) {
  constexpr size_t kMinGroup = 4;
  std::vector<Region> kept;
  std::set<Region> seen;
  for (const auto& [start, unused] : off) {
    if (!seen.insert(start).second) continue;
    std::vector<Region> group{start};
    for (size_t k = 0; k < group.size(); ++k)
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) {
          const Region next{group[k].first + dx, group[k].second + dy};
          if (off.count(next) && seen.insert(next).second) group.push_back(next);
        }
    if (group.size() >= kMinGroup) kept.insert(kept.end(), group.begin(), group.end());
  }
  return kept;
}

// The misfit of missions m and m+1 (the larger way round, overall in
// stats in metres) and the neighbourhood they are judged with, overall and
// by region; a warning where it had to widen.
PairReach fit_pair(const MissionSet& missions, size_t m, const OccupancyMap& map_m, const OccupancyMap& map_next,
                   const VolumetricConfig& config, int threads, ChangeStats* stats) {
  const Mission &a = missions.missions[m], &b = missions.missions[m + 1];
  const double size = region_size(a, b, config);
  SurfaceMisfit ab, ba;
  parallel_for(2, threads, [&](size_t way) {
    if (way == 0) ab = surface_misfit(a, map_next, config, size);
    else ba = surface_misfit(b, map_m, config, size);
  });
  const double misfit = std::max(ab.overall, ba.overall);
  PairReach reach{pair_neighbourhood(misfit, config.neighbourhood), {}, size};
  std::map<Region, std::pair<int, double>> off;  // regions needing a wider reach: it, and their misfit
  for (const SurfaceMisfit* way : {&ab, &ba})
    for (const auto& [region, misfit_there] : way->regions) {
      const int wider = pair_neighbourhood(misfit_there, reach.overall);
      if (wider <= reach.overall) continue;
      auto& [r, most] = off[region];
      r = std::max(r, wider), most = std::max(most, misfit_there);
    }
  double worst = 0.0;  // voxels, of the regions judged wider
  Region worst_at{0, 0};
  for (const Region& region : in_groups(off)) {
    const auto& [r, most] = off.at(region);
    reach.wider[region] = r;
    if (most > worst) worst = most, worst_at = region;
  }
  if (!stats) return reach;
  stats->misfit[m] = misfit * config.resolution;
  stats->misfit_regions[m] = reach.wider.size();
  if (reach.overall > config.neighbourhood) {
    char text[480];
    std::snprintf(text, sizeof text,
                  "missions '%s' and '%s' hold the surfaces they share %.0f mm apart (median, along the surfaces' "
                  "normals; 8-17 mm on aligned test scenes): their alignment is off by about that much, so change within "
                  "%.2f m of what the other holds is not counted (neighbourhood %d voxels, not %d); check the "
                  "alignment", a.name.c_str(), b.name.c_str(), 1000.0 * misfit * config.resolution,
                  reach.overall * config.resolution, reach.overall, config.neighbourhood);
    stats->warnings.emplace_back(text);
  }
  if (!reach.wider.empty()) {
    char text[480];
    std::snprintf(text, sizeof text,
                  "missions '%s' and '%s' hold the surfaces they share apart in %zu regions of %.0f m x %.0f m (up to "
                  "%.0f mm, around x %.0f m, y %.0f m): their alignment is off there, so change there near what the "
                  "other holds is not counted; check the alignment",
                  a.name.c_str(), b.name.c_str(), reach.wider.size(), size, size,
                  1000.0 * worst * config.resolution, (worst_at.first + 0.5) * size, (worst_at.second + 0.5) * size);
    stats->warnings.emplace_back(text);
  }
  return reach;
}

}  // namespace

MissionPoints detect_changes(const MissionSet& missions, const std::vector<const OccupancyMap*>& maps,
                             const VolumetricConfig& config, int threads, ChangeStats* stats) {
  const size_t n = missions.missions.size();
  const PairThresholds thresholds = pair_thresholds(missions, config);
  if (maps.size() != n) throw Error("detect_changes: one map per mission expected");
  MissionPoints out;
  if (stats) *stats = ChangeStats(n);
  Looks looks(missions);
  for (size_t m = 0; m < n; ++m) looks.share[m] = one_look_share(missions.missions[m], *maps[m], config);
  note_stations(missions, looks, config, thresholds, stats);
  std::vector<PairReach> reach;
  for (size_t m = 0; m + 1 < n; ++m) reach.push_back(fit_pair(missions, m, *maps[m], *maps[m + 1], config, threads, stats));
  for (size_t m = 0; m < n; ++m) {
    const Mission& mission = missions.missions[m];
    PointBits bits = no_bits(mission);
    mark_changes(missions, m, *maps[m], m > 0 ? maps[m - 1] : nullptr, m + 1 < n ? maps[m + 1] : nullptr, config,
                 thresholds, looks, reach, threads, bits);
    add_mission(out, stats, missions, m, bits, config, threads);
  }
  return out;
}

MissionPoints detect_changes_windowed(const MissionSet& missions,
                                      const std::function<std::unique_ptr<OccupancyMap>(size_t)>& build_map,
                                      const VolumetricConfig& config, int threads, ChangeStats* stats) {
  const size_t n = missions.missions.size();
  if (n == 0) return {};
  const PairThresholds thresholds = pair_thresholds(missions, config);
  MissionPoints out;
  if (stats) *stats = ChangeStats(n);
  // A point's bit against the previous mission and its bit against the
  // next are decided apart, so one pair of consecutive maps at a time
  // suffices: map m+1 is built while only map m lives, then both missions
  // are marked against each other and map m goes.
  Looks looks(missions);
  std::unique_ptr<OccupancyMap> earlier = build_map(0);
  looks.share[0] = one_look_share(missions.missions[0], *earlier, config);
  PointBits earlier_bits = no_bits(missions.missions[0]);
  std::vector<PairReach> reach;  // per pair, filled as both of its maps live
  for (size_t m = 0; m + 1 < n; ++m) {
    std::unique_ptr<OccupancyMap> later = build_map(m + 1);
    looks.share[m + 1] = one_look_share(missions.missions[m + 1], *later, config);
    PointBits later_bits = no_bits(missions.missions[m + 1]);
    reach.push_back(fit_pair(missions, m, *earlier, *later, config, threads, stats));
    mark_changes(missions, m, *earlier, nullptr, later.get(), config, thresholds, looks, reach, threads, earlier_bits);
    mark_changes(missions, m + 1, *later, earlier.get(), nullptr, config, thresholds, looks, reach, threads,
                 later_bits);
    earlier = std::move(later);  // map m goes
    add_mission(out, stats, missions, m, earlier_bits, config, threads);
    earlier_bits = std::move(later_bits);
  }
  add_mission(out, stats, missions, n - 1, earlier_bits, config, threads);
  note_stations(missions, looks, config, thresholds, stats);
  return out;
}

}  // namespace lista::raycast
