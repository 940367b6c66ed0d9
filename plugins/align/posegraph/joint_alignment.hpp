// The multi-mission pose graph: every mission's odometry chain plus the
// inter-mission loop closures, initialised from the closures (a spanning tree
// over missions from the reference) and optimised jointly. Split from the
// stage so that tests can drive it with plain options.
#pragma once

#include "global_search.hpp"
#include "loop_closures.hpp"
#include "pose_graph.hpp"
#include "scan_odometry.hpp"

#include <lista/context.hpp>
#include <lista/missions.hpp>

#include <map>
#include <string>

namespace lista::align {

struct JointAlignmentOptions {
  KeyframeOptions keyframes;
  CandidateOptions candidates;
  VerifyOptions verify;
  ConsistencyOptions consistency;
  // A mission left unlinked by the Scan Context closures is searched for on
  // the linked missions' maps (global_search.hpp) unless this is off.
  bool global_search = true;
  GlobalSearchOptions global;
  // Per mission: a station cut from a mission without poses
  // (unposed_stations.hpp). Between two such, a whole-map placement that
  // replaces the closures' is routine, said in an info line, not a warning.
  std::vector<char> unposed_station;
  PoseGraphOptions graph;
  ScanEdgeOptions scan_edges;
  double odometry_sigma_translation = 0.02;  // m per consecutive-scan edge
  double odometry_sigma_rotation = 0.005;    // rad
  double closure_sigma_translation = 0.05;   // m
  double closure_sigma_rotation = 0.01;      // rad
  bool fix_reference_mission = true;         // else only its first pose
  int refine_rounds = 1;                     // rounds of closures proposed by proximity after a solve
  double refine_radius = 3.0;                // m between keyframes in the common frame
  // Scan-to-scan edges that raise the final closures' RMS residual above
  // scan_disagreement times (and 1 cm above) its value without them are
  // left out, judged per mission, when this check is on.
  bool check_scan_disagreement = true;
  double scan_disagreement = 3.0;
};

struct JointAlignmentReport {
  double submap_distance = 0.0;  // m either side the keyframe submaps span (grown: KeyframeOptions::submap_min_points)
  size_t keyframes = 0, candidates = 0, verified = 0, consistent = 0, proximity = 0, final_closures = 0;
  size_t intra = 0;  // consistent closures within one mission
  size_t global = 0;  // closures found by the whole-map search
  size_t global_replaced = 0;  // weakly linked mission pairs whose closures the whole maps overruled
  size_t scan_edges_tried = 0, scan_edges = 0;  // scan-to-scan registrations tried / accepted
  size_t scan_map_missions = 0;  // missions registered scan to local map (ScanEdgeOptions::map_use)
  size_t station_missions = 0;  // missions whose pairs were judged as stations' (ScanEdgeReport::stations)
  size_t station_links_tried = 0, station_links = 0;  // whole-scan registrations between missions' stations
  // Three or more stations laid out together (station_vote.hpp): the pairs
  // with a whole-map placement, those that agree with the layout, and the
  // layout's mean share of a station's points where another saw through.
  size_t station_pairs = 0, station_pairs_agreeing = 0;
  double station_conflict = 0.0;
  std::vector<char> linked;  // per mission: linked to the first by the final closures
  std::vector<size_t> closures_per_mission;  // consistent closures to other missions
  double initial_cost = 0.0, final_cost = 0.0;
  // RMS translation residual of the final closures (m), solved with and
  // without the scan-to-scan edges (0 when there are none), and the number
  // of missions whose edges were left out for raising it
  // (JointAlignmentOptions::scan_disagreement).
  double closure_residual_with_scan_edges = 0.0, closure_residual_without_scan_edges = 0.0;
  size_t scan_edges_left_out = 0;
};

// Whether scan-to-scan edges disagree with the loop closures: the closures'
// RMS residual solved with them is above `ratio` times (and 1 cm above) the
// residual solved without them.
bool scan_edges_disagree(double residual_with, double residual_without, double ratio);

// The warning when fewer than half of at least 8 neighbouring-scan
// registrations of mission `mission` were accepted ("" otherwise). It names
// both causes: scans that overlap too little to register (a 16-beam scanner
// outdoors, on correct poses), and poses that do not belong to the scans.
std::string scan_edges_warning(const std::string& mission, size_t accepted, size_t tried);

// The warning for a mission of stations whose registered pairs (`edges`,
// graph nodes from `offset`) leave some stations unlinked to the rest (""
// when all are linked): those stand where poses.txt puts them.
std::string unlinked_stations_warning(const Mission& mission, size_t offset, const std::vector<PoseGraphEdge>& edges);

// The missions whose scan-to-scan edges, left out for disagreeing with the
// closures, are tried again onto local maps (ScanEdgeOptions::map_scans):
// those that had edges and were left out (every one when `all_left_out`,
// else the blamed), registered scan to scan so far (not `on_maps`
// already), when local maps are allowed. Kept only if they agree.
std::vector<size_t> missions_to_retry_on_maps(const std::vector<char>& had_edges, const std::vector<char>& blamed,
                                              bool all_left_out, const std::vector<bool>& on_maps, bool maps_allowed);

// With three or more missions, those whose scan-to-scan edges are to blame:
// taking out their edges alone (residual_without_each[m], NaN for a
// mission without edges) brings the closures' residual down from
// residual_with_all as scan_edges_disagree says. Two missions: none (the
// caller then leaves out all).
std::vector<char> missions_to_blame(double residual_with_all, const std::vector<double>& residual_without_each,
                                    double ratio);

// Returns a copy of `missions` (point data shared) with corrected scan poses and
// to_common. Throws lista::Error naming any mission that links to no other.
MissionSet align_missions(const MissionSet& missions, const JointAlignmentOptions& options, Context& context,
                          JointAlignmentReport& report);

}  // namespace lista::align
