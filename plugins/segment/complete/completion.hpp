// Object completion: grows change clusters that a volumetric difference left
// incomplete into the whole object, using each mission's full point cloud.
//
// Why: an object moved by less than its own size (or replaced by another on
// the same spot) keeps occupying the overlap of its two poses, so only the
// non-overlapping parts of it change. The paper names this as its main loss
// of recall (Exp. 3) and as the cause of clusters too small to describe.
//
// The rule, for consecutive missions m and n = m + 1:
//  0. Floor (`floor_share` > 0): an object with at least floor_share of its
//     points within the floor clearance of its local floor (below) is the
//     floor itself, flagged by the difference where beams graze uneven
//     ground; it is dropped before pairing, so it pairs with nothing, and
//     ids are renumbered 0..n-1 when any is dropped.
//     0b (`thin_height` > 0): an object thinner than thin_height whose points
//     lie, static_share of them, in voxels every neighbouring mission also
//     holds above its floor (the static check of rule 5) is a horizontal
//     surface that did not change, such as a table top grazed by beams.
//     So is one whose own mission continues its surface (points within
//     2 cm of its median height) on at least `thin_surface_sides` of its
//     four sides: a patch the other mission's beams grazed without
//     hitting. It runs with rule 0, before pairing, and renumbers the same
//     way; it does not depend on static_check.
//  1. Pairs. An object a of m and an object b of n whose bounding boxes are at
//     most `pair_gap` apart are a candidate pair (both slivers of one object
//     seen at two poses). Pairs are tried greedily by increasing gap, each
//     object in at most one completed pair, so the result does not depend
//     on order; at equal gaps (overlapping boxes are all 0 m apart) the
//     pair with the nearer centroids (horizontal) goes first
//     (`pair_order`); with `pair_retry` a pair refused by step 4 leaves both
//     objects free for their next candidates (the nearest box may be a third
//     object's, touching the first as closely as its true partner does),
//     without it each object is offered its nearest candidate only.
//     With `join_fragments`, other objects of a pair member's mission that
//     its growth reaches (within one voxel) and that no completed pair
//     holds are fragments of the same object when the pair's shapes agree
//     with them in the seed: a short move with a turn leaves slivers at
//     both ends of a desk, and one of them alone does not reach the
//     other's end. The pair is grown again with them (their boxes join
//     the region, up to three rounds; both sides' fragments, else one
//     side's); if those shapes agree within half the allowance of step 4,
//     they are joined into the pair's object and the ids renumbered, else
//     the pair is judged alone.
//  2. Region. The growth region R is the union box of a and b grown by
//     `box_margin`, reaching down to the local floor. For a rigid object moved
//     by less than its size, the part that did not change (the overlap of its
//     two poses) lies between the two slivers, hence inside R.
//  3. Growth. a grows in m's cloud, b in n's cloud: a breadth-first walk over
//     occupied voxels (edge `voxel`, 26-neighbourhood) from the object's own
//     voxels, staying inside R, above the local floor clearance, and
//     off points that another object of that mission already owns.
//  4. Check. Neither growth may want out of R: occupied voxels next to it
//     but outside R, over `max_leak` per voxel it grew into, mean it is part
//     of something bigger (a wall, the desk the object touches): then, with
//     `leak_growth` own_box, both grow again inside the union of the two objects'
//     boxes without margin (R less the margin: the object, not what it
//     touches), else the pair is left alone. And both
//     grown objects must have the same shape as one rigid object would: height above the floor and the two sides of their
//     footprint rectangle (lista::geometry) agree within max(`shape_tolerance` x the larger,
//     `shape_slack`). With `still_check`, the two grown objects, registered
//     onto each other (lista::objreg), must fit better at the registered
//     pose than where they stand, and that pose must move them (5 cm or 5
//     degrees): two growths into the same static thing between two changes
//     (a desk between a box taken away and a barrel put down) fit best
//     unmoved. Failing either check, both objects are kept as they were, so an
//     unrelated pair of changes never swallows the structure between them.
//  4b. Connected fragments (`join_connected`): two objects of one mission
//     that no completed pair holds, boxes at most pair_gap apart and voxels
//     not touching (segment.carve cut such apart on purpose), are one object
//     when a growth from one (as in 3, inside the union of their boxes grown
//     by box_margin, down to the floor, with no leak check: a table's top
//     reaches past its legs' boxes) reaches the other over points it adds,
//     and at most 1 - static_share of those lie in voxels every
//     neighbouring mission also holds (rule 5's test): the material between
//     them changed with them. A removed table whose top the difference
//     could not confirm leaves its legs as separate clusters, joined by the
//     top; two boxes taken off a bench that stays are connected only over
//     the bench, which the other mission holds, and stay two. Joined objects
//     go into the largest and ids are renumbered 0..n-1; rule 5 then grows
//     the joined object in its whole box.
//  5. Self-completion (every object, `self_complete`): the same growth inside
//     the object's own box grown by `box_margin`, reaching down to the floor
//     for objects standing on it. The difference cannot confirm change next
//     to the floor (the floor voxel is occupied in both missions), so objects
//     lose their base; this gives it back. If the growth wants out of the box
//     (the object touches a wall), the base below its lowest detected part,
//     in the columns that part occupies, is added, and with `leak_growth` own_box
//     what the growth reaches inside the object's own box (no margin).
//     With `static_check`, when at least `static_share` of the points a
//     self-completion would add lie in voxels also occupied (above that
//     mission's local floor) in every neighbouring mission (m - 1 and m + 1,
//     where they exist), those points are left out: what the others hold at
//     the same place did not change. A sliver of phantom change on a static
//     wall or partition (residual misalignment) then stays a sliver instead
//     of growing into the whole structure. Below the share the growth is
//     kept whole: a short move whose two slivers were not paired overlaps
//     its other pose too. The pair growth (rules 1-4) is exempt.
//  6. Fragments (`nested_share` > 0): an object with at least nested_share of
//     its points inside the box of a larger object of the same mission (grown
//     by half a voxel) joins it. Growth never takes points another object
//     owns, so an object cut in two by the difference (two slivers of one
//     short move, a leg apart from the rest) stays two clusters interleaved in
//     one box; measured on exp3, fsc, hall and demo, every such nesting was
//     one true object. Ids are renumbered 0..n-1 when any object joins another.
//  7. Floor (every object): the local floor under an object standing on it
//     (its lowest point at most kOnFloorGap above) becomes its floor_z, the
//     height descriptors measure from (describe.learned).
// The local floor around an object: the `floor_percentile` of the lowest point
// per 0.2 m cell gives a first guess, refined to the median of the points just
// above it; object points must lie max(`floor_clearance`, 4 x its noise)
// above it (robust to ramps; no global ground model needed).
#pragma once

#include <lista/missions.hpp>
#include <lista/objects.hpp>

#include <cstddef>
#include <string>

namespace lista::segment {

// An object whose lowest point is at most this far above the local floor
// stands on it (metres); farther up it stands on something else.
constexpr float kOnFloorGap = 0.3f;

// Rule 0 counts a point as floor within the floor clearance, but never
// higher than this above the floor (metres): on rough ground 4 sigma of
// its noise reaches 0.18 m, a pallet's height.
constexpr float kFloorObjectHeight = 0.1f;

enum class PairOrder { centroid, gap };
enum class LeakGrowth { own_box, base };

struct CompletionConfig {
  double voxel = 0.1;             // m, connectivity grid of the growth
  double pair_gap = 1.0;          // m, largest box-to-box gap of a pair
  double box_margin = 0.15;       // m, growth region = union box of the pair grown by this
  double floor_clearance = 0.02;  // m, least clearance above the floor (4 sigma of its noise if more)
  double floor_percentile = 0.1;  // of the per-cell lowest points around the pair
  double shape_tolerance = 0.25;  // relative disagreement of the pair's extents allowed
  double shape_slack = 0.15;      // m, absolute disagreement always allowed
  double max_leak = 0.1;          // leaked voxels per voxel grown into, at most
  // A pair whose growth is refused frees its two objects for their next
  // candidates (true); or each object is offered its nearest candidate only.
  bool pair_retry = true;
  // Candidates at the same gap (boxes that overlap are all 0 m apart) are
  // tried by the horizontal distance of their centroids, or in id order (gap).
  PairOrder pair_order = PairOrder::centroid;
  // A pair's growth that reaches other free objects of its own mission
  // tries again with them joined (true): kept if the joined shapes agree.
  bool join_fragments = true;
  // A pair whose two grown objects fit best where they stand (registered,
  // the pose moves them under 5 cm and 5 degrees, or they fit better
  // unmoved) grew into a static thing between two changes: refused.
  bool still_check = true;
  // Rule 4b: free objects of one mission that its cloud connects over
  // changed points are joined (a table's legs without its top).
  bool join_connected = true;
  bool self_complete = true;      // also complete every object inside its own box (rule 5)
  // When a growth leaks out of its region (the object touches a wall or
  // furniture): rule 5 also adds what the growth reaches inside the
  // object's own box, rules 1-4 grow the pair inside the union of its two
  // boxes (own_box); or only the base, and no pair completion (base).
  LeakGrowth leak_growth = LeakGrowth::own_box;
  bool static_check = true;       // rule 5 adds nothing every neighbouring mission also holds
  double static_share = 0.8;      // ... once at least this share of the growth is held there
  double nested_share = 0.5;      // rule 6: share of a fragment inside a larger object's box; 0 = off
  double floor_share = 0.9;       // rule 0: share of an object within the floor clearance that makes it floor; 0 = off
  double thin_height = 0.05;      // rule 0b: m, thinner objects held by every neighbouring mission are dropped; 0 = off
  int thin_surface_sides = 3;     // rule 0b: ... and those whose own mission continues their surface on this many sides; 0 = off
  int threads = 1;
};

struct CompletionStats {
  size_t pairs = 0;         // candidate pairs examined
  size_t completed = 0;     // pairs whose growth was accepted
  size_t rejected = 0;      // pairs not completed (no floor, a leak, shapes that differ, growths that stand still)
  size_t self_completed = 0;  // objects grown by rule 5
  size_t points_added = 0;    // over all objects
  size_t points_static = 0;   // rule 5 candidates left out as static (static_check)
  size_t floors = 0;          // objects given their floor_z (rule 7)
  size_t absorbed = 0;        // fragments joined to a larger object (rule 6)
  size_t joined = 0;          // fragments joined into a completed pair's object (rule 1)
  size_t connected = 0;       // objects joined to another of their mission over changed points (rule 4b)
  size_t floor_only = 0;      // objects dropped as the floor itself (rule 0)
  size_t thin_static = 0;     // thin objects every neighbouring mission also holds (rule 0b)
  size_t thin_surface = 0;    // thin patches of a larger surface of their own mission (rule 0b)
  // One line per candidate pair: completed, or why not (no floor, a growth
  // leaking out of its region, grown shapes that disagree, grown objects
  // that fit best where they stand); for `-v`.
  std::vector<std::string> pair_notes;
  // One line per object self-completion looked at (rule 5): how it grew.
  std::vector<std::string> object_notes;
};

// `missions` must be the aligned missions the objects were detected in (same
// names, same order as objects.missions). Objects keep their ids and order
// unless rule 0 drops floor or rule 1, 4b or 6 joins fragments (then ids are
// renumbered 0..n-1 in order).
ObjectSet complete_objects(const ObjectSet& objects, const MissionSet& missions,
                           const CompletionConfig& config, CompletionStats* stats = nullptr);

}  // namespace lista::segment
