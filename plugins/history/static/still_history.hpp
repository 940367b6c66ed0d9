// history.static: follows each changed object into the neighbouring missions
// where it stood still, so that its history covers every mission it was in.
//
// Volumetric differencing compares neighbouring missions only. A crate moved
// between missions A and B and left alone in C is found in A and B; in C its
// points equal B's and nothing flags them, yet it is the same moved crate
// (data contract, sect. 3: its points are changed in every mission). This
// looks for the object at the same place in the next mission (or, for an
// object that changed against the next one, in the previous one), and while
// it is there, adds it to that mission as an object of the same history.
//
// An added or removed object found standing still on the side it changed
// against, and gone from its place on the other side, was given the wrong
// status (a kitchen unit new in B and left in C, called removed): with
// follow_contradictions it is followed that way too, and it and its copies
// take the status the two sides show.
#pragma once

#include <lista/groups.hpp>
#include <lista/matches.hpp>
#include <lista/missions.hpp>
#include <lista/objects.hpp>

#include <string>
#include <vector>

namespace lista::history {

struct StillConfig {
  double radius = 0.1;             // m: a point of the other mission within it shows the same surface
  double min_still_share = 0.6;    // share of the object's points shown again, to call it still there
  double min_share_gap = 0.3;      // by how much more than in the mission it changed against
  double max_reported_share = 0.2; // share already covered by that mission's own objects: stop there
  bool follow_contradictions = true;  // also follow an added/removed object toward its change (below)
};

// One candidate looked at: where an object was looked for, and what was found.
struct StillCandidate {
  int source = -1;       // the object followed (a copy after the first step)
  uint32_t mission = 0;  // the mission it was looked for in
  double still_share = 0.0;     // its points shown again there
  double gone_share = -1.0;     // shown on the other side, where it changed (first step; -1: not checked)
  double reported_share = 0.0;  // covered by that mission's own objects
  int copy = -1;                // id of the object added, or -1
  std::string verdict;          // "still" ("still, added" / "still, removed": status corrected), "changed", "reported", "no points"
};

struct StillResult {
  ObjectSet objects;  // the input objects, then the copies
  Matches matches;    // an entry per object; histories include the copies
  Groups groups;      // a copy in its source's group (empty when no groups came in)
  std::vector<StillCandidate> candidates;
  size_t copies = 0;
  std::vector<int> corrected;  // ids of added/removed objects whose status the missions contradicted
};

// `groups` may be null. Objects without an entry in `matches` are not
// followed. Deterministic: objects are visited in input order.
StillResult extend_histories(const MissionSet& missions, const ObjectSet& objects, const Matches& matches,
                             const Groups* groups, const StillConfig& cfg, int threads);

}  // namespace lista::history
