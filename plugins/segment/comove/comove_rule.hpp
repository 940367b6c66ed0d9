// Pieces that moved together are one object.
//
// A sparse scanner at table height sees a table as its legs: the top is hit
// edge on, by a ring or two, and nothing the difference finds connects the
// legs. Each leg then becomes an object of its own in both missions, and a
// moved table is reported as three or four short "moved" legs, each
// registered on its own (a post has no yaw) and none paired with the table.
// What ties the legs together is that they moved as one: one rigid motion
// carries all of them onto the other mission's legs.
//
// For each pair of consecutive missions (m, m+1), among the pieces of each
// that are slender (height >= slender_ratio x the short side of the
// footprint; posts, legs, uprights, edge strips) and changed against the
// other mission:
//  1. Hypotheses. Two pieces i, j of m at most join_gap apart (box to box)
//     and two pieces k, l of m+1 likewise, whose horizontal centroid
//     distances agree within position_tolerance, give a yaw and a
//     translation carrying i onto k and j onto l. A motion under
//     position_tolerance and 10 degrees is no move: skipped; so is a seed
//     pair of m that the pieces of m+1 cover where it stands (it did not
//     move; a symmetric layout turned about its middle lands on itself).
//  2. Evidence. A piece of m is covered when at least cover_share of its
//     points, moved by the hypothesis, lie within cover_radius of the
//     slender pieces of m+1 (and the reverse for m+1 with the inverse). All
//     four seeds must be covered; then every covered piece within join_gap
//     of the set joins it, on each side, until none does.
//  3. Choice. Hypotheses with at least two pieces on each side and a joined
//     footprint of at most max_extent are taken by their total points, most
//     first, each piece in at most one.
// The search spends at most a fixed number of coverage tests per mission
// pair (a regular grid of posts offers hypotheses without end) and says
// when it stopped (ComoveStats::searches_cut).
// A piece the other mission did not see (an occluded leg) has no evidence
// and stays apart. Joined pieces become one object (points in id order, the
// lowest floor_z); objects of different missions are never joined, and
// joins in one mission from both of its neighbours chain. Ids are
// renumbered 0..n-1 when anything joined, kept otherwise.
#pragma once

#include <lista/objects.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lista::segment {

struct ComoveConfig {
  double slender_ratio = 2.0;        // a piece's height over its footprint's short side, at least (0 = any piece)
  double join_gap = 2.0;             // m, box-to-box gap between pieces of one object
  double position_tolerance = 0.25;  // m, agreement of the seed pairs' centroid distances; smallest move
  double cover_radius = 0.15;        // m, a moved point this near the other mission's pieces is covered
  double cover_share = 0.5;          // share of a piece's points covered for it to join
  double max_extent = 3.0;           // m, longest footprint side of a joined object
};

struct ComoveStats {
  size_t joins = 0;   // joined objects made
  size_t joined = 0;  // pieces that went into them
  // Missions m whose search with m+1 stopped at its budget (a regular grid
  // of slender pieces offers hypotheses without end): some joins there may
  // be missing.
  std::vector<uint32_t> searches_cut;
};

ObjectSet join_comoving(const ObjectSet& in, const ComoveConfig& config, ComoveStats* stats = nullptr);

}  // namespace lista::segment
