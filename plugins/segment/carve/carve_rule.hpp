// Carving: cuts out of a change cluster another mission's object that fits
// inside it, when the cluster is that object touching something else.
//
// Why: the volumetric difference and voxel connectivity see two changed
// objects that touch in one mission (a crate moved against a shelf that also
// moved, a desk turned against an added cabinet) as one cluster. Reported as
// one object it matches neither, and the move is lost. The object's other
// pose, in the neighbouring mission, is often a cluster of its own: its
// shape is a template for the cut.
//
// The rule, for each object H (host) and each object T (template) of a
// neighbouring mission (m - 1 or m + 1):
//  1. Cull. T needs `min_points`, a footprint at least `min_width` wide
//     (a leg, a panel or a fragment fits within the tolerance of almost
//     any surface) and at most H's height + `tolerance`; H needs
//     2 x min_points, a footprint of at most kMaxHostArea, and must be
//     bigger (footprint area over kBiggerArea x T's, or taller by
//     `min_height_step`), else they are the same object.
//  2. Fit. T is turned about z in `yaw_step` steps and slid over H's box in
//     `voxel` steps (heights unchanged in the common frame, or moved by the
//     difference of the two floors when both are known); fit = share of T's
//     points (voxel-subsampled, at most kMaxSamples) within `tolerance` of
//     a point of H, measured on a voxel grid (up to one cell more). Of the
//     poses with fit >= min_fit the tightest wins (points in a host point's
//     own cell count twice); it is refined once at half the steps, and T's
//     top band (its top fifth, at least two voxels) must fit as well.
//  3. Cut. With fit >= `min_fit`, H's points within `tolerance` of the
//     placed T are the carved part E, the others the rest; connected parts
//     of the rest (voxel connectivity at 2 x voxel) under `min_points` join E.
//  4. Check. E and the rest must each hold `min_share` of H's points, and
//     their tops must differ by `min_height_step`: where they are as tall,
//     the cut could run through one object's continuous top (a box fits
//     into any corner of a cabinet as tall), so H is kept whole. And they
//     must stand beside each other: at most `max_overlap` of the smaller
//     part's floor cells (2 x voxel) may lie under the other too. A partial
//     view of an object fits inside a fuller view of it (or of its like),
//     and the cut then leaves parts above each other (a chair's seat and its
//     back); touching objects share only the cells of their contact.
// Fits are measured for every candidate pair, then taken best first (ties
// by the objects' points, not their order), each object in at most one
// carve (as host or template), so the result does not depend on the order
// of objects or on the thread count. E keeps H's place; each connected part
// of the rest becomes an object after it; ids are renumbered 0..n-1 when
// anything was carved (else the set comes back as it was).
#pragma once

#include <lista/objects.hpp>

#include <cstddef>
#include <functional>
#include <vector>

namespace lista::segment {

// A host whose footprint is less than this multiple of the template's (and
// which is not taller by min_height_step) is the same object, not two.
constexpr double kBiggerArea = 1.3;
// Template points used for the fit search (voxel-subsampled, then strided).
constexpr size_t kMaxSamples = 400;
// Hosts with a larger footprint (m^2) are not searched: structure or a heap.
constexpr float kMaxHostArea = 25.f;

struct CarveConfig {
  double voxel = 0.05;            // m, search step and grid cell
  double tolerance = 0.08;        // m, a template point fits within this of a host point
  double yaw_step = 5.0;          // degrees
  double min_fit = 0.8;           // share of the template's points that must fit
  double min_share = 0.15;        // least share of the host's points in each part
  double min_height_step = 0.1;   // m, least difference between the parts' tops
  double max_overlap = 0.3;       // most of the smaller part's floor cells also under the other
  size_t min_points = 30;         // smallest template, and smallest separate part of the rest
  double min_width = 0.3;         // m, narrowest template footprint (shorter side)
  int threads = 1;
  std::function<bool()> cancelled;  // optional: checked per host; the input comes back unchanged
};

// One carve: the host's and the template's ids (in the input), the share of
// the template's samples that fit, and the points on each side.
struct Carve {
  int host = -1, tmpl = -1;
  double fit = 0.0;
  size_t carved = 0, rest = 0;
};

struct CarveStats {
  size_t candidates = 0;  // host/template pairs whose fit was searched
  size_t fitted = 0;      // pairs that fitted (fit >= min_fit)
  size_t carved = 0;      // hosts cut
  size_t parts = 0;       // objects made from the rests (beyond the one each host leaves)
  std::vector<Carve> carves;
};

ObjectSet carve_objects(const ObjectSet& in, const CarveConfig& config, CarveStats* stats = nullptr);

}  // namespace lista::segment
