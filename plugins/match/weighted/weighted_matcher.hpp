// Correspondences between the objects of consecutive missions by the paper's
// weighted distance  w = alpha * norm(physical) + beta * norm(descriptor),
// solved optimally per mission pair, then statuses, histories and confidences.
//
// Normalisation. The paper min-max normalises both distances over the
// candidate pairs. With near-identical descriptors (two chairs of one model)
// min-max stretches pure descriptor noise to the full [0,1] range, letting
// noise overrule the physical term when identical objects swap places. The
// default ("max") therefore divides by the largest candidate distance only
// (min-max with the minimum pinned at 0, the smallest possible distance);
// "minmax" gives the paper's exact form.
//
// Groups. Descriptor groups are imperfect (K is estimated; a partial view of
// a chair can land in another class), so by default the group constraint is
// soft: a cross-group pair pays `group_penalty` on top of w. "hard" forbids
// cross-group pairs (the paper's "within each group"); "ignore" drops groups.
//
// Gates. A pair is a candidate only if its centroids are at most
// `max_distance` metres apart (0, the default: no limit, since a site's
// scale is not known and an object may cross it; the size and shape gates
// keep unlike objects apart and the physical term prefers near partners),
// its sizes agree as one rigid object's would (height and the
// sides of the footprint rectangle (lista::geometry) differ by at most
// max(`max_size_change` x the larger, `size_slack`); 0 turns it off), its descriptor distance is at most `max_descriptor_distance` (if > 0)
// and its weighted cost is at most `max_cost`. With the default max_cost =
// alpha + beta (+ shape_weight x (1 - min_shape_fit)) every same-group pair
// inside the other gates is a candidate and a cross-group pair must be
// clearly closer or more similar than the worst candidate to survive its
// penalty.
//
// Confidence = evidence x (0.5 + 0.5 x c), a move's also x its shape fit,
// the lower of a move's two ends'.
// c of a move: 0.5 x (1 - ambiguity) + 0.5 x group confidence; of an
// unmatched object: 0.5 x how far its nearest rejected candidate stayed
// from the gate + 0.5 x group confidence. Evidence: how much surface the
// object shows (on 34 sets unmatched reports under 300 points were right
// 7 % of the time, over 3000 points 87 %, while c ranked them backwards;
// the fit ranks moves better still; docs/matching.md, "Confidence").
//
// Shape check (not in the paper). Two changes of similar size and
// descriptor (a removed desk, an added desk of another model) are not a move
// unless one rigid object explains both: every pair that passed the gates is
// registered (PairFit) and its fit in [0, 1] adds shape_weight x (1 - fit) to
// the cost; fit < min_shape_fit rules the pair out. shape_weight = 0 and
// min_shape_fit = 0 give the paper's cost and skip the registration.
#pragma once

#include <Eigen/Geometry>

#include <lista/descriptors.hpp>
#include <lista/groups.hpp>
#include <lista/matches.hpp>
#include <lista/objects.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace lista::matching {

struct WeightedMatchConfig {
  double alpha = 0.5;               // weight of the physical (centroid) distance
  double beta = 0.5;                // weight of the descriptor distance
  std::string normalization = "max";  // "max" or "minmax"
  std::string group_mode = "soft";  // "soft", "hard" or "ignore"
  double group_penalty = 0.5;       // soft mode: added to cross-group pairs
  double max_distance = 0.0;        // m: physical gate; 0 = none
  double max_size_change = 0.6;     // size gate: relative change of height / extents; 0 = off
  double size_slack = 0.15;         // m: size change always allowed (partial views, noise)
  double max_descriptor_distance = 0.0;  // descriptor units; 0 = no gate
  double max_cost = -1.0;           // weighted gate; < 0 means alpha + beta
  double shape_weight = 0.5;        // weight of the shape misfit (1 - fit); needs a PairFit
  double min_shape_fit = 0.8;       // shape gate: smallest fit of a pair; 0 = off
  bool far_side_explains = true;    // 3+ missions: an object changed mainly against its other neighbour is no candidate
  // Evidence 1 - exp(-v / evidence_voxels), v = the object's occupied
  // evidence_voxel cubes (its observed surface); confidence = evidence x
  // (0.5 + 0.5 x the matching and group terms), x the shape fit for a move.
  // evidence_voxels = 0: the matching and group terms alone.
  double evidence_voxel = 0.1;      // m
  double evidence_voxels = 40.0;
};

// 1 - exp(-v / evidence_voxels) for the object's v occupied voxel cubes of
// edge evidence_voxel; 1 when evidence_voxels is 0.
double surface_evidence(const Object& object, const WeightedMatchConfig& cfg);

// How well each (earlier, later) pair of objects fits as one rigid object,
// in [0, 1] (1 = every point explained); a negative value rules the pair
// out whatever min_shape_fit (the floor gate). Called once per mission pair with
// every candidate that passed the other gates.
using PairFit = std::function<std::vector<double>(const std::vector<std::pair<const Object*, const Object*>>&)>;

// Every object of `objects` gets one ObjectChange. `groups` may be null;
// `fit` may be empty only when shape_weight and min_shape_fit are 0.
Matches match_weighted(const ObjectSet& objects, const DescriptorSet& descriptors,
                       const Groups* groups, const WeightedMatchConfig& cfg,
                       std::string* warning = nullptr, const PairFit& fit = {});

}  // namespace lista::matching
