// Which missions the loop closures link, and how: the closures found and
// vetted between keyframes (Scan Context candidates, verification, the
// consistency vote, whole-map searches for weak or missing links), and the
// first placement of every mission they give. Internal to align.posegraph.
#pragma once

#include "joint_alignment.hpp"
#include "stopwatch.hpp"

#include <Eigen/Geometry>

#include <vector>

namespace lista::align {

struct MissionClosures {
  std::vector<Keyframe> keyframes;
  std::vector<Closure> verified;  // every verified closure, the whole-map searches' included
  std::vector<Closure> closures;  // those the vote kept, and the searches' placements
};

// Keyframes, closures and the warnings about them (placements a rival fit
// nearly matched, pairs or missions the whole maps placed); fills the
// report's counts and prints progress.
MissionClosures find_mission_closures(const MissionSet& set, const JointAlignmentOptions& o, Context& ctx,
                                      JointAlignmentReport& report, const Stopwatch& clock);

// Initial map -> common transforms: a spanning tree over missions from the
// reference, each link the best-fitting closure between the two missions.
std::vector<Eigen::Isometry3d> initial_transforms(const MissionSet& set, const std::vector<Keyframe>& kf,
                                                  const std::vector<Closure>& closures,
                                                  const JointAlignmentReport& report);

// Missions linked to the first through inter-mission closures.
std::vector<char> linked_to_first(size_t missions, const std::vector<Keyframe>& kf,
                                  const std::vector<Closure>& closures);

}  // namespace lista::align
