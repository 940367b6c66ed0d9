#include "tf_tree.hpp"

#include "trajectory.hpp"

#include <lista/error.hpp>

#include <console_bridge/console.h>
#include <geometry_msgs/TransformStamped.h>
#include <tf2/exceptions.h>

#include <algorithm>
#include <limits>

namespace lista::bag {

void TfTree::add(const std::vector<FrameTransform>& transforms, bool is_static) {
  for (const auto& t : transforms) {
    Edge& e = parent_of_[t.child_frame];
    e.parent = t.parent_frame;
    e.is_static = is_static;
    if (!is_static) stamps_of_[t.child_frame].push_back(t.stamp);
    pending_.emplace_back(t, is_static);
  }
}

void TfTree::finish() {
  double first = std::numeric_limits<double>::infinity(), last = -first;
  for (const auto& [t, is_static] : pending_)
    if (!is_static) first = std::min(first, t.stamp), last = std::max(last, t.stamp);
  // tf2 forgets what is older than its cache time: keep the whole bag.
  const double span = last >= first ? last - first : 0.0;
  buffer_ = std::make_unique<tf2::BufferCore>(ros::Duration(span + 10.0));
  // tf2 reports through console_bridge (repeated stamps, old data): the
  // reader says what matters itself.
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_NONE);
  for (const auto& [t, is_static] : pending_) {
    geometry_msgs::TransformStamped m;
    m.header.stamp = ros::Time(std::max(0.0, t.stamp));
    m.header.frame_id = t.parent_frame;
    m.child_frame_id = t.child_frame;
    m.transform.translation.x = t.transform.translation().x();
    m.transform.translation.y = t.transform.translation().y();
    m.transform.translation.z = t.transform.translation().z();
    const Eigen::Quaterniond q(t.transform.linear());
    m.transform.rotation.x = q.x(), m.transform.rotation.y = q.y(), m.transform.rotation.z = q.z(), m.transform.rotation.w = q.w();
    buffer_->setTransform(m, "bag", is_static);
  }
  pending_.clear();
  pending_.shrink_to_fit();
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
    if (const auto s = stamps_of_.find(f); s != stamps_of_.end()) coarsest = std::max(coarsest, lista::bag::median_interval(s->second));
    f = it->second.parent;
  }
  return coarsest;
}

std::optional<Eigen::Isometry3d> TfTree::lookup(const std::string& target, const std::string& source, double stamp) const {
  geometry_msgs::TransformStamped m;
  try {
    m = buffer_->lookupTransform(target, source, ros::Time(std::max(0.0, stamp)));
  } catch (const tf2::ExtrapolationException&) {
    return std::nullopt;
  } catch (const tf2::TransformException& e) {
    throw Error("tf: no transform from frame '" + source + "' to '" + target + "' (" + e.what() + ")");
  }
  const auto& r = m.transform.rotation;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(m.transform.translation.x, m.transform.translation.y, m.transform.translation.z);
  return T;
}

}  // namespace lista::bag
