#include "tf_tree.hpp"

#include <lista/error.hpp>

#include <algorithm>

namespace lista::bag {

void TfTree::add(const std::vector<FrameTransform>& transforms, bool is_static) {
  for (const auto& t : transforms) {
    Edge& e = parent_of_[t.child_frame];
    e.parent = t.parent_frame;
    e.is_static = is_static;
    if (is_static)
      e.fixed = t.transform;
    else
      e.samples.push_back({t.stamp, t.parent_frame, t.child_frame, t.transform});
  }
}

void TfTree::finish() {
  for (auto& [child, e] : parent_of_)
    if (!e.is_static) {
      e.moving.emplace(std::move(e.samples));
      e.samples.clear();
    }
}

bool TfTree::knows(const std::string& frame) const {
  if (parent_of_.count(frame)) return true;
  return std::any_of(parent_of_.begin(), parent_of_.end(), [&](const auto& e) { return e.second.parent == frame; });
}

std::string TfTree::root_of(const std::string& frame) const {
  std::string f = frame;
  for (size_t steps = 0; steps <= parent_of_.size(); ++steps) {
    const auto it = parent_of_.find(f);
    if (it == parent_of_.end()) return f;
    f = it->second.parent;
  }
  throw Error("tf: the frames above '" + frame + "' form a loop");
}

bool TfTree::moves_under_root(const std::string& frame) const {
  std::string f = frame;
  for (size_t steps = 0; steps <= parent_of_.size(); ++steps) {
    const auto it = parent_of_.find(f);
    if (it == parent_of_.end()) return false;
    if (!it->second.is_static) return true;
    f = it->second.parent;
  }
  return false;
}

double TfTree::median_interval(const std::string& frame) const {
  double coarsest = 0.0;
  std::string f = frame;
  for (size_t steps = 0; steps <= parent_of_.size(); ++steps) {
    const auto it = parent_of_.find(f);
    if (it == parent_of_.end()) break;
    if (it->second.moving) coarsest = std::max(coarsest, it->second.moving->median_interval());
    f = it->second.parent;
  }
  return coarsest;
}

std::optional<Eigen::Isometry3d> TfTree::to_root(const std::string& frame, double stamp) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  std::string f = frame;
  for (size_t steps = 0; steps <= parent_of_.size(); ++steps) {
    const auto it = parent_of_.find(f);
    if (it == parent_of_.end()) return T;
    const Edge& e = it->second;
    if (e.moving) {
      const std::optional<Eigen::Isometry3d> at = e.moving->at(stamp);
      if (!at) return std::nullopt;
      T = *at * T;
    } else {
      T = e.fixed * T;
    }
    f = e.parent;
  }
  throw Error("tf: the frames above '" + frame + "' form a loop");
}

std::optional<Eigen::Isometry3d> TfTree::lookup(const std::string& target, const std::string& source, double stamp) const {
  if (root_of(target) != root_of(source))
    throw Error("tf: no transform from frame '" + source + "' to '" + target + "': they hang under different roots ('" +
                root_of(source) + "', '" + root_of(target) + "') and never connect");
  const auto root_T_source = to_root(source, stamp), root_T_target = to_root(target, stamp);
  if (!root_T_source || !root_T_target) return std::nullopt;
  if (target == root_of(target)) return *root_T_source;  // the usual case: exact, no inverse
  return root_T_target->inverse() * *root_T_source;
}

}  // namespace lista::bag
