// Internal: a bag's /tf and /tf_static as a tree of frames, looked up at a
// cloud's stamp: each moving edge interpolated between its two samples
// around the stamp (translation linearly, rotation by slerp; a sample's own
// stamp gives the sample exactly, as the folders' poses.txt would), static
// edges as recorded, the chain composed from each frame up to the lowest
// frame the two chains share.
#pragma once

#include "trajectory.hpp"

#include <lista_bag/messages.hpp>

#include <map>
#include <optional>

namespace lista::bag {

class TfTree {
 public:
  void add(const std::vector<FrameTransform>& transforms, bool is_static);
  // Sorts what add() gathered; call once, after the last add().
  void finish();

  bool knows(const std::string& frame) const;
  // The frame at the top of `frame`'s chain (itself when it has no parent).
  std::string root_of(const std::string& frame) const;
  // Whether a transform that is not static lies between `frame` and its root.
  bool moves_under_root(const std::string& frame) const;
  // T_target_source at `stamp`: nullopt when `stamp` lies outside the time
  // a moving edge of the chain covers (never extrapolated); throws
  // lista::Error when the frames never connect. A chain of static edges
  // holds at any stamp.
  std::optional<Eigen::Isometry3d> lookup(const std::string& target, const std::string& source, double stamp) const;
  // The median time between the samples of the moving transforms above
  // `frame` (the coarsest of them); 0 when none moves.
  double median_interval(const std::string& frame) const;

 private:
  struct Edge {
    std::string parent;
    bool is_static = false;
    Eigen::Isometry3d fixed = Eigen::Isometry3d::Identity();  // static: parent_T_child
    std::vector<StampedPose> samples;                          // moving: parent_T_child over time
    std::optional<Trajectory> moving;                          // made from samples by finish()
  };
  // `frame`, its parent, ... up to its root.
  std::vector<std::string> chain_of(const std::string& frame) const;
  // ancestor_T_frame at `stamp` (`ancestor` on frame's chain), or nullopt
  // outside a moving edge's time.
  std::optional<Eigen::Isometry3d> up_to(const std::string& frame, const std::string& ancestor, double stamp) const;

  std::map<std::string, Edge> parent_of_;  // child frame -> its edge
};

}  // namespace lista::bag
