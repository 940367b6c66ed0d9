// The joint pose graph of align_missions: one node per scan of every
// mission, the edges within each mission (odometry, scan to scan) and the
// loop closures between keyframes, with what the alignment asks of it.
// Internal to align.posegraph.
#pragma once

#include "joint_alignment.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <vector>

namespace lista::align {

// Nodes of every mission in order (mission m's scan s is node offset[m] + s).
struct Graph {
  std::vector<size_t> offset;  // first node of each mission
  std::vector<Eigen::Isometry3d> nodes;
  std::vector<bool> fixed;
  std::vector<PoseGraphEdge> within;  // edges inside each mission: odometry and scan-to-scan
};

inline size_t node_of(const Graph& g, const Keyframe& k) { return g.offset[k.mission] + k.scan; }
inline size_t mission_of(const Graph& g, size_t node) {
  return size_t(std::upper_bound(g.offset.begin(), g.offset.end(), node) - g.offset.begin()) - 1;
}

// Every mission's scans at `to_common[m]` times their poses, chained by
// odometry edges; the reference mission fixed (or its first pose).
Graph odometry_graph(const MissionSet& set, const std::vector<Eigen::Isometry3d>& to_common,
                     const JointAlignmentOptions& o);

// The closure as a relative pose between the two scans' sensor poses.
Eigen::Isometry3d closure_measurement(const MissionSet& set, const std::vector<Keyframe>& kf, const Closure& c);

// Keyframe frame in the common frame under the current node estimates.
Eigen::Isometry3d frame_in_common(const MissionSet& set, const Graph& g, const Keyframe& k);

// The closures as robust edges between their keyframes' nodes.
std::vector<PoseGraphEdge> closure_edges(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                                         const std::vector<Closure>& closures, const JointAlignmentOptions& o);

// Solves the graph's own edges plus `closures`; the nodes take the solution.
PoseGraphSummary solve(Graph& g, const std::vector<PoseGraphEdge>& closures, PoseGraphOptions options);

// Verified closures whose measurement the current estimate agrees with.
std::vector<Closure> agreeing(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                              const std::vector<Closure>& closures, const ConsistencyOptions& o);

// Root mean square of the closures' translation residuals (m) under the
// graph's current estimate.
double closure_rms(const MissionSet& set, const Graph& g, const std::vector<Keyframe>& kf,
                   const std::vector<Closure>& closures);

// Copies of the missions (point data shared) with the graph's poses: each
// keeps its own map frame up to one rigid transform (to_common), anchored
// at its first scan; the rest of the correction goes into the scan poses.
MissionSet with_graph_poses(const MissionSet& set, const Graph& g);

}  // namespace lista::align
