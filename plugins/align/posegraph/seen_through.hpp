// What a scan's sensor saw through: its nearest return in each direction
// (1-degree bins). A point another scan puts well in front of that return
// stands where this sensor's beam passed freely, so one of the two scans is
// misplaced (or the point moved between them). Station layouts are judged
// by it (station_vote.hpp). Internal to align.posegraph.
#pragma once

#include "global_search.hpp"
#include "loop_closures.hpp"

#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

namespace lista::align {

class SeenThrough {
 public:
  // `points` in the sensor's frame (a keyframe's submap: its own scan when
  // the keyframe is a station).
  explicit SeenThrough(const Cloud& points);
  // Share of `points` (in their own frame) that `sensor_T_points` puts in
  // front of the nearest return around their direction (the 3 x 3 bins
  // about it) by more than max(0.5 m, 5 %), among those whose direction
  // holds a return at all; judged on at most kMaxPoints of them, evenly
  // spread.
  double share_in_front(const Cloud& points, const Eigen::Isometry3d& sensor_T_points) const;

  static constexpr size_t kMaxPoints = 4096;

 private:
  static constexpr int kColumns = 360, kRows = 180;
  std::vector<float> nearest_;  // m per bin, infinity where nothing returned
};

// The shares of y's points that a_T_b (mission a to mission b) puts in
// front of x's nearest returns, summed over every x of `keyframes` in one of
// the two missions and y in the other (seen[i] is keyframes[i]'s);
// `shares` counts the shares summed.
double conflicts_between(const std::vector<Keyframe>& keyframes_all, const std::vector<size_t>& keyframes,
                         const std::vector<SeenThrough>& seen, size_t a, size_t b, const Eigen::Isometry3d& a_T_b,
                         size_t& shares);

// How much a placement of mission b on mission a, both scanned from
// stations, contradicts what their stations saw: the shares of each
// station's points it puts where a station of the other mission saw
// through, averaged over their station pairs both ways.
class PairConflicts {
 public:
  PairConflicts(const std::vector<Keyframe>& keyframes, size_t a, size_t b);
  double of(const Eigen::Isometry3d& a_T_b) const;

 private:
  const std::vector<Keyframe>& kf_;
  size_t a_, b_;
  std::vector<size_t> keyframes_;  // of missions a and b
  std::vector<SeenThrough> seen_;
};

// Between two missions scanned from stations the plan view can favour a
// half-turned fit of a near-symmetric room; what the stations saw cannot
// (station_vote.hpp). Of the verified placements (overlap >= min_overlap),
// the one with the fewest conflicts (PairConflicts) overrules the plan
// view's choice (`plan_view`; none: the incumbent's, judged only where a
// verified placement agrees with it) when it has under half as many. With
// neither a choice nor an incumbent, it is taken when it has under half as
// many as every distinct rival.
struct StationJudgement {
  bool overruled = false;
  std::optional<GlobalPlacement> choice;  // the placement to take; none: the incumbent's, or nothing
  std::string note;                       // what was overruled and why, when it was
};
StationJudgement judge_station_placements(const std::vector<Keyframe>& keyframes, size_t a, size_t b,
                                          const PlacementSearch& search, const GlobalSearchOptions& options,
                                          const std::optional<Eigen::Isometry3d>& incumbent,
                                          const std::optional<GlobalPlacement>& plan_view);

}  // namespace lista::align
