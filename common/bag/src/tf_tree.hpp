// Internal: a bag's /tf and /tf_static, looked up at a cloud's stamp with
// tf2's BufferCore (interpolation, chains of frames).
#pragma once

#include <lista_bag/messages.hpp>

#include <map>
#include <optional>
#include <tf2/buffer_core.h>

namespace lista::bag {

class TfTree {
 public:
  void add(const std::vector<FrameTransform>& transforms, bool is_static);
  // Loads what add() gathered into tf2; call once, after the last add().
  void finish();

  bool knows(const std::string& frame) const;
  // The frame at the top of `frame`'s chain (itself when it has no parent).
  std::string root_of(const std::string& frame) const;
  // Whether a transform that is not static lies between `frame` and its root.
  bool moves_under_root(const std::string& frame) const;
  // T_target_source at `stamp`: nullopt when `stamp` lies outside the time
  // the chain covers (tf2 would extrapolate); throws lista::Error when the
  // frames never connect.
  std::optional<Eigen::Isometry3d> lookup(const std::string& target, const std::string& source, double stamp) const;
  // The median time between the samples of the moving transforms above
  // `frame` (the coarsest of them); 0 when none moves.
  double median_interval(const std::string& frame) const;

 private:
  struct Edge {
    std::string parent;
    bool is_static = false;
  };
  std::map<std::string, Edge> parent_of_;
  std::map<std::string, std::vector<double>> stamps_of_;  // moving edges: child frame -> stamps
  std::vector<std::pair<FrameTransform, bool>> pending_;
  std::unique_ptr<tf2::BufferCore> buffer_;
};

}  // namespace lista::bag
