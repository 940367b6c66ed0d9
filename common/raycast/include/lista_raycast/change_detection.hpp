// The change decision both volumetric backends share. A backend builds one
// occupancy map per mission and exposes it through OccupancyMap; this code
// then classifies every original point against the neighbouring missions.
#pragma once

#include <lista/context.hpp>
#include <lista/missions.hpp>
#include <lista/stage.hpp>
#include <lista_raycast/volumetric_config.hpp>
#include <lista_raycast/voxel.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lista::raycast {

// Read access for one thread (backends cache tree paths in it, so never share).
class OccupancyReader {
 public:
  virtual ~OccupancyReader() = default;
  // False if the voxel was never observed; else its log-odds in `out`.
  virtual bool logodds(const Voxel& v, float& out) = 0;
  // True if the mission's own scans saw the voxel free at least as often as
  // occupied: something stood there for part of the mission only (dynamic
  // evidence). False where the backend keeps no counts and cannot tell.
  virtual bool seen_free(const Voxel&) { return false; }
};

class OccupancyMap {
 public:
  virtual ~OccupancyMap() = default;
  virtual std::unique_ptr<OccupancyReader> reader() const = 0;
};

// What building one mission's map cost and produced.
struct MapStats {
  uint64_t rays = 0;             // beams cast (hits and max-range misses)
  uint64_t voxel_visits = 0;     // free-space voxels on the beams, before de-duplication
  uint64_t voxels_walked = 0;    // of those, the ones a backend actually stepped through
  uint64_t occupied_voxels = 0;  // P > occupied_threshold after all scans
  uint64_t free_voxels = 0;      // observed, not occupied
};

struct ChangeStats {
  explicit ChangeStats(size_t missions = 0)
      : changed_points(missions, 0),
        changed_voxels(missions, 0),
        seen_free_points(missions, 0),
        misfit(missions > 1 ? missions - 1 : 0, 0.0),
        misfit_regions(misfit.size(), 0) {}
  std::vector<uint64_t> changed_points, changed_voxels;  // per mission
  std::vector<uint64_t> seen_free_points;                // of the changed points, per mission
  std::vector<double> one_look_share;                    // per mission (one_look_share)
  std::vector<double> misfit;                            // per pair m, m+1: surface_misfit, m
  std::vector<uint64_t> misfit_regions;                  // per pair: regions judged wider for their misfit
  std::vector<std::string> notes;                        // pairs taken as stations
  std::vector<std::string> warnings;                     // pairs judged wider for their misfit
};

// Share of a mission's points (every 16th) whose voxel one scan of it hit
// and nothing else observed: 0.75-1.0 on TLS stations, 0.14-0.64 on 18
// many-scan sets. Where both missions of a pair were scanned from stations
// (lista_geometry/stations.hpp) and have over kStationShare of their
// points so, and change_threshold was not given, one hit against one miss
// is change where the miss went through the surface (docs/volumetric.md,
// steps 5 and 6): a mission of stations gets no second look to wait for.
double one_look_share(const Mission& mission, const OccupancyMap& map, const VolumetricConfig& config);
inline constexpr double kStationShare = 0.5;

// The change_threshold of each pair of consecutive missions (value[m]: m
// and m+1). A voxel gets at most one update per scan, so with few scans P
// stays near 0.5: one scan each gives at most prob_hit against at least
// prob_miss, 0.3 apart at the defaults, under change_threshold 0.35. Such a
// pair takes the strongest evidence its scans can give as change (every
// scan of one saw the voxel occupied, every scan of the other saw it free):
// its threshold is that difference less kStrongestEvidenceSlack, and a note
// says so. When change_threshold was given explicitly it holds, and a
// warning says the pair can show no change.
struct PairThresholds {
  std::vector<double> value;
  std::vector<std::string> notes, warnings;
};
inline constexpr double kStrongestEvidenceSlack = 0.01;
PairThresholds pair_thresholds(const MissionSet& missions, const VolumetricConfig& config);

// Points of mission m are changed when, against mission m-1 or m+1, their
// voxel's probability exceeds the other's by more than the pair's threshold
// (pair_thresholds; the
// other mission must have observed the voxel) and no voxel within
// `neighbourhood` of it is occupied in the other mission. Output: one set per
// mission, common frame, original points with their provenance and channels,
// in scan then file order (deterministic for any thread count). A changed
// point whose voxel its own mission also saw free (OccupancyReader::
// seen_free) carries seen_free_in_own_mission besides its neighbour bits.
MissionPoints detect_changes(const MissionSet& missions,
                             const std::vector<const OccupancyMap*>& maps,
                             const VolumetricConfig& config, int threads,
                             ChangeStats* stats = nullptr);

// detect_changes with maps built on demand, in mission order, by
// `build_map(m)`: map m+1 is built while only map m is held, and map m is
// freed once both are marked against each other, so at most two maps live
// at once, whatever the number of missions (a map can take gigabytes
// outdoors). The same result as building all maps first.
MissionPoints detect_changes_windowed(const MissionSet& missions,
                                      const std::function<std::unique_ptr<OccupancyMap>(size_t)>& build_map,
                                      const VolumetricConfig& config, int threads,
                                      ChangeStats* stats = nullptr);

// What a volumetric stage does around its backend's maps, the same for
// every backend: its StageInfo (the name, version and texts given; the
// ports and volumetric_params), and its run: the missions checked, how each
// pair is judged said, the changes detected with progress, the metrics
// recorded. `build(m, threads, stats)` builds mission m's map. Maps are built
// in mission order, at most two held (detect_changes_windowed), each with
// every thread; with `side_by_side`, two missions' maps are built at once,
// the threads shared (for a backend whose map building is serial).
StageInfo volumetric_stage_info(std::string name, std::string version, std::string summary, std::string doc);
using MapBuilder = std::function<std::unique_ptr<OccupancyMap>(size_t m, int threads, MapStats& stats)>;
Outputs run_volumetric_stage(const Inputs& inputs, Context& ctx, const VolumetricConfig& config,
                             const MapBuilder& build, bool side_by_side);

}  // namespace lista::raycast
