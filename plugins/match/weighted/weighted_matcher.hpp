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
// soft: a cross-group pair pays `groups.penalty` on top of w. "hard" forbids
// cross-group pairs (the paper's "within each group"); "ignore" drops groups.
//
// Gates. A pair is a candidate only if its centroids are at most
// `distance_gate.max_distance` metres apart (off by default: a site's
// scale is not known and an object may cross it; the size and shape gates
// keep unlike objects apart and the physical term prefers near partners),
// its sizes agree as one rigid object's would (height and the
// sides of the footprint rectangle (lista::geometry) differ by at most
// max(`size_gate.max_change` x the larger, `size_gate.slack`)), its
// descriptor distance is at most `descriptor_gate.max_distance` (off by
// default) and its weighted cost is at most the cost gate's. With the
// automatic gate alpha + beta (+ shape_weight x (1 - min_fit)) every same-group pair
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
// the cost; a fit under the shape gate's min_fit rules the pair out.
// shape_weight = 0 with the shape gate off gives the paper's cost and skips
// the registration.
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

namespace lista::match {

enum class Normalization { max, minmax };  // see "Normalisation" above
enum class GroupMode { soft, hard, ignore };

struct WeightedMatchConfig {
  double alpha = 0.5;               // weight of the physical (centroid) distance
  double beta = 0.5;                // weight of the descriptor distance
  double shape_weight = 0.5;        // weight of the shape misfit (1 - fit); needs a PairFit
  Normalization normalization = Normalization::max;
  struct GroupConstraint { GroupMode mode = GroupMode::soft; double penalty = 0.5; } groups;  // penalty: soft mode's
  struct DistanceGate { bool enabled = false; double max_distance = 10.0; } distance_gate;   // m
  // Relative change of height / extents, and the change always allowed
  // (partial views, noise; m).
  struct SizeGate { bool enabled = true; double max_change = 0.6, slack = 0.15; } size_gate;
  struct DescriptorGate { bool enabled = false; double max_distance = 1.0; } descriptor_gate;
  // automatic: alpha + beta + shape_weight x (1 - the shape gate's bar()).
  struct CostGate { bool automatic = true; double max_cost = 1.0; } cost_gate;
  struct ShapeGate {
    bool enabled = true;
    double min_fit = 0.8;
    // The fit a pair needs: min_fit, or 0 when off (a negative fit, the
    // floor gate's refusal, never passes).
    double bar() const { return enabled ? min_fit : 0.0; }
  } shape_gate;
  bool far_side_explains = true;    // 3+ missions: an object changed mainly against its other neighbour is no candidate
  // Evidence 1 - exp(-v / voxels), v = the object's occupied voxel cubes of
  // edge `voxel` (its observed surface); confidence = evidence x (0.5 + 0.5 x
  // the matching and group terms), x the shape fit for a move. Off: the
  // matching and group terms alone.
  struct Evidence { bool enabled = true; double voxel = 0.1, voxels = 40.0; } evidence;
};

// 1 - exp(-v / evidence.voxels) for the object's v occupied voxel cubes of
// edge evidence.voxel; 1 when the evidence is off.
double surface_evidence(const Object& object, const WeightedMatchConfig& cfg);

// How well each (earlier, later) pair of objects fits as one rigid object,
// in [0, 1] (1 = every point explained); a negative value rules the pair
// out whatever the shape gate (the floor gate). Called once per mission pair with
// every candidate that passed the other gates.
using PairFit = std::function<std::vector<double>(const std::vector<std::pair<const Object*, const Object*>>&)>;

// Every object of `objects` gets one ObjectChange. `groups` may be null;
// `fit` may be empty only when shape_weight is 0 and the shape gate off.
Matches match_weighted(const ObjectSet& objects, const DescriptorSet& descriptors,
                       const Groups* groups, const WeightedMatchConfig& cfg,
                       std::string* warning = nullptr, const PairFit& fit = {});

}  // namespace lista::match
