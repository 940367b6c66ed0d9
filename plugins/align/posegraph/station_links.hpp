// Whole-scan registrations between the stations of different missions:
// where both missions were scanned from stop-and-go stations (or hold one
// scan), their keyframe submaps are single scans downsampled for driving
// missions, and the closures between them carry a driving mission's
// uncertainty. Once the graph has placed the missions, each station is
// registered onto the nearest stations of every earlier such mission with
// the scans' own resolution and accuracy, as scan edges within a mission
// are. Internal to align.posegraph (docs/alignment.md, "Stations").
#pragma once

#include "mission_graph.hpp"
#include "scan_odometry.hpp"

#include <lista/missions.hpp>

#include <functional>
#include <set>
#include <vector>

namespace lista::align {

struct StationLinks {
  std::vector<PoseGraphEdge> edges;                 // between nodes of different missions
  std::set<std::pair<size_t, size_t>> pairs;        // (earlier, later) missions some edge links
  size_t tried = 0;
};

// Per mission: whether its scans are stations (one scan counts as one).
std::vector<char> station_missions(const MissionSet& set);

// Each station of a station mission registered onto the max(1,
// o.neighbours) nearest stations (under g's current estimate, within
// o.max_range) of each earlier station mission, from that estimate; kept
// if it passes the stations' gates (station_edge_options). Edges at the
// scan edges' sigmas in x, y and yaw, and at `vertical`'s sigma_translation
// and sigma_rotation (the closures') in height and level.
StationLinks station_link_edges(const MissionSet& set, const Graph& g, const std::vector<char>& stations,
                                const ScanEdgeOptions& o, const PoseGraphEdge& vertical, int threads,
                                const std::function<bool()>& cancelled = {});

}  // namespace lista::align
