// Scan-to-scan registration edges within each mission: metric relative poses
// measured from the scans themselves. Odometry can carry a bias (a path a few
// per mille too long, a heading creeping one way) that loop closures cannot
// see when every mission shares it; a registered pair of nearby scans can.
#pragma once

#include "pose_graph.hpp"

#include <lista/missions.hpp>
#include <lista_alignkit/registration.hpp>

#include <functional>
#include <optional>

#include <vector>

namespace lista::align {

using namespace alignkit;  // common/alignkit: clouds, registration, levelling

enum class MapUse { never, when_pairs_fail, always };

struct ScanEdgeOptions {
  int neighbours = 0;           // each scan registered onto this many following scans (0: off)
  double max_range = 40.0;      // m; points farther from the sensor are dropped (sparse, noisy)
  // m; points lower than this above the scan's ground are dropped (0: kept):
  // the ground says nothing about x, y and yaw. Off by default: it helps the
  // open sites' poses but not their change reports (docs/bench/alignment.md).
  double ground_clearance = 0.0;
  RegistrationOptions registration;  // registration.voxel: the finest downsampling
  // Dense scans are downsampled coarser (x1.25 steps) until at most this many
  // points are left: registration time grows with points, accuracy hardly.
  size_t max_points = 15000;
  // Scan-to-map: each scan registered, in order, onto a local map of the
  // map_scans scans before it, placed by the registrations before (one edge
  // per scan). A sparse sensor's single scan puts its nearest points a ring
  // gap away whatever the pose; several scans fill the gaps. Used per
  // mission (map_use): when fewer than half of its scan-to-scan pairs
  // register (three quarters when they are judged along planes: the steps
  // no registered pair spans keep the odometry's bias), always, or never;
  // map_scans 1 is never too.
  int map_scans = 3;
  MapUse map_use = MapUse::when_pairs_fail;
  // Overlap both ways (one way onto a local map), as for loop closures; the
  // RMSE point to point or along the target's planes (scan_pair_gates); a
  // result far from the odometry is a wrong minimum, not a correction.
  RegistrationGates gates;
  // The overlap gate for a mission of stop-and-go stations (scans farther
  // apart than their points reach), whose pairs overlap little however
  // well they fit: the whole-map search's (GlobalSearchOptions::min_overlap).
  double station_min_overlap = 0.3;
  bool robust = true;  // under the graph's robust loss
  // Edges constrain x, y and yaw only (PoseGraphEdge::planar): height and
  // level stay the odometry's, which sparse scans do not register better.
  double sigma_translation = 0.005;     // m, horizontal
  double sigma_rotation = 0.001;        // rad, yaw
};

// The points of a scan (sensor frame) higher than `clearance` above its
// ground: the 2nd percentile of their heights, levelled by the scan's pose.
// Returned whole if clearance is 0 or fewer than 100 points would remain.
Cloud above_ground(const Cloud& scan, const Eigen::Isometry3d& pose, double clearance);

// A scan's points as its registrations use them: within max_range, the
// ground left out if asked, downsampled to about max_points.
Cloud scan_cloud(const Scan& scan, const ScanEdgeOptions& options);

// The options a mission of stop-and-go stations registers its pairs with:
// the overlap gate of whole maps (station_min_overlap), no robust loss.
ScanEdgeOptions station_edge_options(const ScanEdgeOptions& options);

// The registration of `source` onto `target` from `guess`, if it passes
// o.gates; `both_ways`: the target's overlap with the source counts too.
std::optional<Eigen::Isometry3d> gated_registration(const PreparedCloud& source, const PreparedCloud& target,
                                                    const Eigen::Isometry3d& guess, const ScanEdgeOptions& o,
                                                    bool both_ways);

// A scan edge between graph nodes: planar, at o's sigmas, robust as o says.
PoseGraphEdge scan_edge(size_t from, size_t to, const Eigen::Isometry3d& measurement, const ScanEdgeOptions& o);

struct ScanEdgeReport {
  size_t tried = 0, accepted = 0;  // the edges used: scan to scan, or scan to map where switched
  std::vector<size_t> tried_per_mission, accepted_per_mission;  // by mission index
  std::vector<bool> scan_to_map;                          // by mission: registered onto local maps
  std::vector<bool> stations;                             // by mission: its pairs judged as stations'
  std::vector<size_t> pairs_tried, pairs_accepted;        // by mission: scan-to-scan, before any switch
};

// Edges between graph nodes: node of scan s of mission m is offsets[m] + s.
// `cancelled` is polled between registrations (the loop takes seconds per
// mission); once it says true the rest is skipped and `on_cancel` throws.
std::vector<PoseGraphEdge> scan_registration_edges(const MissionSet& missions, const std::vector<size_t>& offsets,
                                                   const ScanEdgeOptions& options, int threads,
                                                   ScanEdgeReport& report,
                                                   const std::function<bool()>& cancelled = {},
                                                   const std::function<void()>& on_cancel = {});

}  // namespace lista::align
