// The merge/split of change clusters across consecutive missions by overlap
// ratio. The overlap of object a with object b is the share of a's points that
// lie inside b's bounding box grown by `margin`:
//
//   inside(a, b) = |{p in a : p in box(b) + margin}| / |a|
//
// For each pair of consecutive missions (m, m+1), in both directions:
//  1. Merge. Two or more objects a1..ak of one mission that each lie inside
//     the same object b of the other mission (inside(ai, b) >= merge_ratio)
//     and are within `merge_gap` of each other (box to box) become one object.
//     Why: an object moved by less than its own size leaves change only where
//     its two poses do not overlap, so its cluster falls into pieces; the
//     other mission's cluster says they are one thing.
//  2. Split. One object a that contains two or more objects b1..bk of the
//     other mission (inside(bj, a) >= split_ratio for each) that do not
//     themselves overlap (inside(bi, bj) < split_ratio) and stand more than
//     `merge_gap` apart is cut into k parts,
//     each point going to the bj whose box is nearest (then nearest centroid).
//     Why: objects that touch in one mission (or one object replaced by
//     several) form one composite cluster there but stand apart in the other.
//     Parts smaller than `min_points` join the largest part.
// The gap decides between the two readings of "several objects inside one":
// pieces within merge_gap of each other are one object broken up (merge),
// pieces farther apart are separate objects (split the other mission's one).
// Merges run first, over all mission pairs, then splits. Objects of missions
// that are not consecutive are never compared.
#pragma once

#include <lista/objects.hpp>

namespace lista::segment {

struct OverlapConfig {
  double margin = 0.05;       // m, bounding boxes grown by this
  double merge_ratio = 0.5;   // share of a fragment inside the other mission's object
  double merge_gap = 0.3;     // m, fragments at most this far apart (box to box)
  double split_ratio = 0.5;   // share of each other-mission object inside the composite
  size_t min_points = 20;     // smallest part of a split
};

struct OverlapStats {
  size_t merged = 0;  // objects absorbed by merges
  size_t split = 0;   // objects cut
};

ObjectSet merge_split_by_overlap(const ObjectSet& in, const OverlapConfig& config, OverlapStats* stats = nullptr);

}  // namespace lista::segment
