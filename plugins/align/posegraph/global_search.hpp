// Whole-map search for a mission that Scan Context could not link to any
// other (or linked by too few closures to trust): the two missions' maps
// seen from above (walls, furniture, vehicles: what stands between band_low
// and band_high over the ground) are correlated over every yaw and
// horizontal offset, coarse then fine, and the best placements are verified
// by registering whole map onto whole map. Scan Context needs two keyframes
// taken near one spot; missions of a few scans each (a survey of scattered
// stations, a sparse log) rarely have such a pair, while their maps still
// overlap.
#pragma once

#include "loop_closures.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <vector>

namespace lista::align {

struct GlobalSearchOptions {
  double cell = 0.25;          // m: plan-view cells of the fine search
  double coarse_cell = 1.0;    // m: of the search over every yaw; grown so a map spans at most max_coarse_cells
  int max_coarse_cells = 80;
  double yaw_step = 3.0 * M_PI / 180.0;  // rad, coarse search
  double band_low = 0.3;       // m above a keyframe's ground: lower points (the ground) are left out
  double band_high = 2.5;      // m: higher points (ceilings, canopies) too
  int hypotheses = 8;          // best coarse placements refined and verified
  // Whole-map registration bars. Maps seen from distant spots share fewer
  // surfaces than two submaps from one spot, so the overlap asked (of the
  // smaller map, within the registration's inlier distance) is lower than a
  // closure's; and the registered placement's plan-view score must beat
  // every distinct rival's by `margin` of itself.
  double min_overlap = 0.3;
  double max_rmse = 0.2;       // m
  double margin = 0.1;
  int max_pairs = 24;           // closures that hold the placement in the pose graph, spread over the query mission
  // Mission pairs the loop closures link by fewer closures than this are
  // checked against the whole maps too: two or three closures on a wrong,
  // half-turned fit of a symmetric room agree with each other.
  int check_below = 4;
};

// One placement of the query mission's map on the reference mission's.
struct GlobalPlacement {
  Eigen::Isometry3d reference_T_query = Eigen::Isometry3d::Identity();  // map to map
  double plan_score = 0.0;   // share of the query's plan-view cells next to the reference's
  double overlap = 0.0, rmse = 0.0;  // of the whole-map registration that verified it (the smaller map's share)
  bool incumbent = false;            // the incumbent's own fit
  double incumbent_plan_score = 0.0; // the incumbent's as given (not registered), when one was given
  std::vector<Closure> closures;  // keyframe pairs that carry it into the pose graph
};

// What the search needs of one mission (its plan view, its whole map
// prepared for registration), made on first use and kept: stations laid
// out together are each searched against many others.
class MissionMaps {
 public:
  MissionMaps(const std::vector<Keyframe>& keyframes, const GlobalSearchOptions& options, const VerifyOptions& verify);
  ~MissionMaps();
  struct Maps;
  const Maps& of(size_t mission);
  const GlobalSearchOptions& options() const { return options_; }
  const RegistrationOptions& registration() const { return registration_; }

 private:
  const std::vector<Keyframe>& keyframes_;
  GlobalSearchOptions options_;
  RegistrationOptions registration_;
  std::map<size_t, std::unique_ptr<const Maps>> made_;
};

// Plan-view candidates, best first (at most options.hypotheses), before
// verification (the second for tests).
std::vector<GlobalPlacement> plan_view_placements(MissionMaps& maps, size_t reference, size_t query, int threads);
std::vector<GlobalPlacement> plan_view_placements(const std::vector<Keyframe>& keyframes, size_t reference,
                                                  size_t query, const GlobalSearchOptions& options, int threads);

// Every plan-view placement (and an `incumbent`, the placement the loop
// closures chose, as one more) refined by registering the query mission's
// whole map onto the reference's (verify's registration), those that
// converge within max_rmse kept, unranked (min_overlap is the caller's).
struct PlacementSearch {
  std::vector<GlobalPlacement> verified;
  Eigen::Vector3d query_centre = Eigen::Vector3d::Zero();  // the query map's centroid, in its frame
};
PlacementSearch verified_placements(const std::vector<Keyframe>& keyframes, size_t reference, size_t query,
                                    const GlobalSearchOptions& options, const VerifyOptions& verify, int threads,
                                    const std::optional<Eigen::Isometry3d>& incumbent = std::nullopt);
// The same from the pair's plan-view candidates (plan_view_placements').
PlacementSearch verified_placements(MissionMaps& maps, size_t reference, size_t query,
                                    std::vector<GlobalPlacement> candidates, int threads,
                                    const std::optional<Eigen::Isometry3d>& incumbent = std::nullopt);

// Two map-to-map placements that put `centre` (in the query's frame) within
// 1 m of each other and turn within 5 deg: one fit, not rivals.
bool same_placement(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, const Eigen::Vector3d& centre);

// A placement as closures between keyframes, so that the pose graph holds it
// like any other: each query keyframe (at most max_pairs, spread along the
// mission; 0: all) with the reference keyframe nearest to where it lands.
std::vector<Closure> placement_closures(const std::vector<Keyframe>& keyframes, size_t reference, size_t query,
                                        const GlobalPlacement& placement, int max_pairs);

// Of the verified placements that overlap min_overlap, the one with the best
// plan-view score, if it clearly beats every verified rival (by `margin`);
// none otherwise. When it is the incumbent's own fit or one that agrees with
// it, or does not beat the incumbent's plan-view score as given by `margin`,
// none either.
std::optional<GlobalPlacement> plan_view_choice(const PlacementSearch& search, const GlobalSearchOptions& options,
                                                const std::optional<Eigen::Isometry3d>& incumbent);

// verified_placements, then plan_view_choice's placement as closures.
std::optional<GlobalPlacement> global_search(const std::vector<Keyframe>& keyframes, size_t reference,
                                             size_t query, const GlobalSearchOptions& options,
                                             const VerifyOptions& verify, int threads,
                                             const std::optional<Eigen::Isometry3d>& incumbent = std::nullopt);

}  // namespace lista::align
