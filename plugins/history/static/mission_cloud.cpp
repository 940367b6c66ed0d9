#include "mission_cloud.hpp"

#include <algorithm>
#include <deque>

namespace lista::history {

std::vector<Eigen::Vector3f> sample(const PointSet& p) {
  const size_t step = std::max<size_t>(1, p.size() / 2000);
  std::vector<Eigen::Vector3f> out;
  for (size_t i = 0; i < p.size(); i += step) out.push_back(p.xyz[i]);
  return out;
}

double share_near(const std::vector<Eigen::Vector3f>& probe, const Cloud& cloud) {
  if (probe.empty()) return 0.0;
  size_t hit = 0;
  for (const auto& p : probe) hit += cloud.grid.any_near(cloud.points.xyz, p);
  return double(hit) / double(probe.size());
}

PointSet take(const Object& object, const Cloud& cloud, float radius, const Cloud* absent) {
  const float floor_z = object.bbox_min.z();
  const Box box{object.bbox_min.array() - radius, object.bbox_max.array() + radius};
  // 0: not looked at, 1: taken, 2: refused (structure).
  std::vector<char> state(cloud.points.size(), 0);
  std::deque<uint32_t> queue;
  auto consider = [&](uint32_t i, bool grown) {
    if (state[i]) return;
    const Eigen::Vector3f& q = cloud.points.xyz[i];
    if (q.z() < floor_z) return;
    if (grown && absent && absent->grid.any_near(absent->points.xyz, q)) {
      state[i] = 2;
      return;
    }
    state[i] = 1;
    queue.push_back(i);
  };
  for (const auto& p : object.points.xyz)
    cloud.grid.for_near(cloud.points.xyz, p, [&](uint32_t i) { consider(i, false); });
  while (!queue.empty()) {
    const uint32_t i = queue.front();
    queue.pop_front();
    cloud.grid.for_near(cloud.points.xyz, cloud.points.xyz[i], [&](uint32_t j) {
      if (box.contains(cloud.points.xyz[j])) consider(j, true);
    });
  }
  std::vector<uint32_t> idx;
  for (uint32_t i = 0; i < state.size(); ++i)
    if (state[i] == 1) idx.push_back(i);
  return cloud.points.select(idx);
}

}  // namespace lista::history
