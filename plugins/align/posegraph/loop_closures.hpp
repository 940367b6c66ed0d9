// Inter-mission loop closures: keyframes with local submaps and Scan Context
// descriptors, candidate retrieval by ring key (k-d tree) and column-shift
// distance, verification by registration, and a consistency vote that drops
// closures disagreeing with the majority of their mission pair.
#pragma once

#include "scan_context.hpp"

#include <lista/missions.hpp>
#include <lista_alignkit/cloud_ops.hpp>
#include <lista_alignkit/registration.hpp>

#include <Eigen/Geometry>
#include <vector>

namespace lista::align {

using namespace alignkit;  // common/alignkit: clouds, registration, levelling

struct KeyframeOptions {
  double keyframe_distance = 1.0;  // m travelled between keyframes
  double keyframe_angle = 0.5;     // rad turned between keyframes
  double submap_distance = 2.0;    // m of trajectory either side joined into the submap
  // While the median submap holds under submap_min_points (after the
  // voxel), every submap grows by submap_distance, up to
  // submap_max_distance either side: a sparse scanner's few scans (a Livox
  // outdoors) register loosely.
  size_t submap_min_points = 0;    // 0: fixed spans
  double submap_max_distance = 10.0;
  double voxel = 0.2;              // m, submap downsampling
  ScanContextOptions scan_context;
};

struct Keyframe {
  size_t mission = 0, scan = 0;
  double travelled = 0.0;   // m of trajectory from the mission's first scan
  double submap_distance = 0.0;  // m of path either side its submap spans (KeyframeOptions: grown when sparse)
  Eigen::Isometry3d frame;  // levelled frame at the scan, in the mission's map frame
  Cloud submap;             // points around it, in `frame`, downsampled
  ScanContext descriptor;
};

// Keyframes of every mission, submaps and descriptors built on `threads` threads.
std::vector<Keyframe> make_keyframes(const MissionSet& missions, const KeyframeOptions& options, int threads);

struct CandidateOptions {
  int neighbours = 10;          // ring-key nearest neighbours examined per query
  double max_descriptor_distance = 0.35;  // Scan Context distance threshold
  int per_pair = 200;  // best candidates kept per mission pair
  // Loops within one mission: a keyframe may close onto one of its own
  // mission intra_min_travel of trajectory earlier.
  bool intra = false;
  double intra_min_travel = 30.0;  // m
};

struct Candidate {
  size_t reference = 0, query = 0;  // keyframe indices; reference is in the earlier mission (or earlier in the same)
  double distance = 1.0;
  double yaw = 0.0;  // query frame heading in the reference frame (rad)
};

// For each keyframe, its best Scan Context match in every earlier mission and,
// with options.intra, in the part of its own mission at least
// intra_min_travel back along the trajectory.
std::vector<Candidate> find_candidates(const std::vector<Keyframe>& keyframes, size_t mission_count,
                                       const CandidateOptions& options, int threads);

struct Closure {
  size_t reference = 0, query = 0;  // keyframe indices
  Eigen::Isometry3d reference_T_query;  // between the keyframes' levelled frames
  double overlap = 0.0, rmse = 0.0, descriptor_distance = 1.0;
};

struct VerifyOptions {
  RegistrationOptions registration;
  double min_overlap = 0.5;  // share of each submap's points with a partner in the other
  double max_rmse = 0.15;    // m
};

// Registers each candidate (guess: the descriptor's yaw) and keeps the good fits.
// `guesses`, when not empty, replaces the yaw guess per candidate.
std::vector<Closure> verify_candidates(const std::vector<Keyframe>& keyframes,
                                       const std::vector<Candidate>& candidates,
                                       const std::vector<Eigen::Isometry3d>& guesses,
                                       const VerifyOptions& options, int threads);

// Map-to-map transform (query mission map -> reference mission map) implied by a closure.
Eigen::Isometry3d implied_map_transform(const std::vector<Keyframe>& keyframes, const Closure& c);

struct ConsistencyOptions {
  double distance = 2.0;  // m: where two closures put the same point may differ by this
  double angle = 0.17;    // rad
  // A rival hypothesis backed by at least `rival_min_support` closures
  // replaces the best-supported one when it puts this much more of the query
  // mission's keyframe points into voxels the reference mission occupies
  // (0: the count alone decides). In symmetric rooms the true and the
  // half-turned fit differed by 1.9-4.1 % of points on the `tiny` rooms
  // (docs/alignment.md). One closure is enough: the whole-map
  // check, not the count, vouches for it (a wrong lone closure puts far
  // fewer points on the reference map).
  double rival_margin = 0.02;
  int rival_min_support = 1;
  double agreement_voxel = 0.3;  // m
};

// A mission pair whose chosen placement a rival hypothesis fits about as
// well (within rival_margin of map agreement): the choice may be wrong.
struct AmbiguousPlacement {
  size_t reference = 0, query = 0;  // missions
  double turn_deg = 0.0;            // rotation between the chosen and the rival map transform
  double shift_m = 0.0;             // how far apart they put the query mission's centre
  double chosen_agreement = 0.0, rival_agreement = 0.0;
};

// Per mission pair, keeps the closures that agree with the best-supported
// one, or with a rival that the whole maps clearly favour (the maps'
// agreement under each measured on `threads`). Pairs where a rival came
// close go to `ambiguous` (if given).
std::vector<Closure> consistent_closures(const std::vector<Keyframe>& keyframes,
                                         const std::vector<Closure>& closures,
                                         const ConsistencyOptions& options,
                                         std::vector<AmbiguousPlacement>* ambiguous = nullptr, int threads = 1);

}  // namespace lista::align
