// Levelling the common frame: which way is up in the aligned maps.
//
// Every stage after alignment takes the common frame's z for up: floors,
// heights above them, upright poses, the ceiling cut. A mission's map frame
// from a SLAM run started on a slope, or by a handheld scanner (FAST-LIO's
// map is its first IMU frame), is tilted, and so is a common frame taken
// from it. Up is read from the maps themselves: planar patches (voxel cells
// whose points spread in two directions and not the third) facing up or
// down (floors, ceilings, table tops) should be normal to it, patches
// facing sideways (walls, cabinet sides) parallel to it. The up u maximises
// sum over floor-like patches of (n.u)^2 minus the same over wall-like ones:
// the top eigenvector of F - W, F and W the sums of n n^T of each kind;
// patches are sorted into the kinds by their angle to the current u, in
// windows narrowing from 30 to 5 degrees, starting from the frame's z.
#pragma once

#include <lista/context.hpp>
#include <lista/missions.hpp>
#include <lista/param_table.hpp>
#include <lista/params.hpp>

#include <Eigen/Geometry>

#include <cstdint>
#include <unordered_map>

namespace lista::alignkit {

struct LevelOptions {
  double voxel = 0.5;         // m: patch size
  size_t max_scans = 100;     // per mission, evenly spread: enough floor and wall for the estimate
  int min_points = 10;        // points a cell needs to be judged a patch
  size_t min_patches = 50;    // planar patches needed (floor-like, or wall-like in two directions)
};

struct LevelEstimate {
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double tilt_deg = 0.0;      // angle between up and the frame's z
  size_t floor_patches = 0;   // within 5 degrees of horizontal / vertical at the end
  size_t wall_patches = 0;
  bool determined = false;    // enough patches to say
};

// Accumulates points (any frame) into voxel cells; estimate() reads up from
// the planar ones.
class UpEstimator {
 public:
  explicit UpEstimator(const LevelOptions& o = {}) : o_(o) {}
  void add(const Eigen::Vector3d& p);
  LevelEstimate estimate() const;

 private:
  struct Cell {
    int n = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();
  };
  LevelOptions o_;
  std::unordered_map<uint64_t, Cell> cells_;
};

// Up in the common frame of `missions` (their to_common and scan poses),
// from at most max_scans scans per mission.
LevelEstimate estimate_common_up(const MissionSet& missions, const LevelOptions& o = {});

// The smallest rotation taking `up` to +z (about the origin).
Eigen::Isometry3d levelling_rotation(const Eigen::Vector3d& up);

// The `level` parameters of every align.* stage that levels: switched by
// `enabled`, tilts from 0.5 deg up to `max_tilt` levelled.
struct LevelConfig {
  bool enabled = true;
  double max_tilt = 20.0;  // deg
};

// align.* stages' last step: the common frame turned so that its z is up,
// when the maps say it is tilted by 0.5 to max_tilt degrees (every
// mission's to_common, so every output follows). Smaller tilts are left
// (a level frame stays as it is, byte for byte); larger ones are warned of
// and left; so is a georeferenced set (origin set: its z is up already).
// Records level_tilt_deg and levelled (0/1).
void level_common_frame(MissionSet& missions, const LevelConfig& config, Context& ctx, const LevelOptions& o = {});

// Declares the group `level` (level.enabled, level.max_tilt) bound to
// `member`, once for every align.* stage, so that its defaults, ranges and
// docs cannot drift apart; the old `level_max_tilt` (0 = never) still reads.
template <class Config>
void bind_level(ParamTable<Config>& table, LevelConfig Config::*member) {
  auto level = table.group("level", member);
  level.bind("enabled", &LevelConfig::enabled,
             "last step: the common frame turned so that its z is up, where its floors and walls say it is tilted "
             "(a SLAM map started on a slope, a handheld scanner's)");
  level.bind("max_tilt", &LevelConfig::max_tilt, "tilts from 0.5 deg up to this are levelled, larger ones left with a warning")
      .range(0.5, 90.0)
      .unit("deg");
  table.renamed("level_max_tilt", "level.max_tilt", "level.enabled", 0.0);
}

}  // namespace lista::alignkit
