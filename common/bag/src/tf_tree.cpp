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

std::vector<std::string> TfTree::chain_of(const std::string& frame) const {
  std::vector<std::string> chain{frame};
  for (size_t steps = 0; steps <= parent_of_.size(); ++steps) {
    const auto it = parent_of_.find(chain.back());
    if (it == parent_of_.end()) return chain;
    chain.push_back(it->second.parent);
  }
  throw Error("tf: the frames above '" + frame + "' form a loop");
}

std::optional<Eigen::Isometry3d> TfTree::up_to(const std::string& frame, const std::string& ancestor, double stamp) const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (std::string f = frame; f != ancestor;) {
    const Edge& e = parent_of_.at(f);
    if (e.moving) {
      const std::optional<Eigen::Isometry3d> at = e.moving->at(stamp);
      if (!at) return std::nullopt;
      T = *at * T;
    } else {
      T = e.fixed * T;
    }
    f = e.parent;
  }
  return T;
}

std::optional<Eigen::Isometry3d> TfTree::lookup(const std::string& target, const std::string& source, double stamp) const {
  const std::vector<std::string> up_source = chain_of(source), up_target = chain_of(target);
  // The lowest frame both chains pass: composing only below it keeps the
  // usual lookups (a frame in its root, a sensor in its body) free of inverses.
  const auto common = std::find_first_of(up_source.begin(), up_source.end(), up_target.begin(), up_target.end());
  if (common == up_source.end())
    throw Error("tf: no transform from frame '" + source + "' to '" + target + "': they hang under different roots ('" +
                up_source.back() + "', '" + up_target.back() + "') and never connect");
  const auto below_source = up_to(source, *common, stamp), below_target = up_to(target, *common, stamp);
  if (!below_source || !below_target) return std::nullopt;
  if (target == *common) return *below_source;
  return below_target->inverse() * *below_source;
}

}  // namespace lista::bag
