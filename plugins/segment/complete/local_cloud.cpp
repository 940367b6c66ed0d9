#include "local_cloud.hpp"

#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <unordered_map>
#include <unordered_set>

namespace lista::segment::completion {

LocalCloud gather(const Mission& mission, const std::vector<Box>& regions, float voxel, int threads) {
  LocalCloud cloud;
  cloud.inv_voxel = 1.f / voxel;
  cloud.points = geometry::points_in_boxes(mission, regions, threads);
  cloud.index();
  return cloud;
}

LocalCloud restrict_to(const LocalCloud& cloud, const std::vector<Box>& regions) {
  LocalCloud out;
  out.inv_voxel = cloud.inv_voxel;
  Box all;
  for (const auto& r : regions) all.extend(r);
  constexpr uint32_t kDropped = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> renumbered(cloud.points.size(), kDropped);
  std::vector<uint32_t> kept;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    if (!all.contains(cloud.points.xyz[i])) continue;
    for (const auto& r : regions)
      if (r.contains(cloud.points.xyz[i])) {
        renumbered[i] = uint32_t(kept.size());
        kept.push_back(uint32_t(i));
        break;
      }
  }
  out.points.reserve(kept.size());
  for (uint32_t i : kept) out.points.push_back_from(cloud.points, i);
  // The kept points keep their order, so the old index filtered is sorted
  // as index() would sort it.
  out.grid.reserve(out.points.size());
  for (const auto& [key, i] : cloud.grid)
    if (renumbered[i] != kDropped) out.grid.emplace_back(key, renumbered[i]);
  return out;
}

bool local_floor(const LocalCloud& cloud, const Box& region, double percentile, double min_clearance, Floor& floor) {
  // The lowest point of each 20-cm column, and every point's height (the
  // order the points come in does not matter: only order statistics of
  // both are read).
  std::unordered_map<uint64_t, float> column_lowest;
  std::vector<float> heights;
  cloud.for_each_in(region, [&](uint32_t i) {
    const Eigen::Vector3f& p = cloud.points.xyz[i];
    const uint64_t column = voxel_key(Eigen::Vector3i(int(std::floor(p.x() * 5.f)), int(std::floor(p.y() * 5.f)), 0));
    const auto [it, fresh] = column_lowest.try_emplace(column, p.z());
    if (!fresh) it->second = std::min(it->second, p.z());
    heights.push_back(p.z());
  });
  if (heights.empty()) return false;
  std::vector<float> lowest;
  lowest.reserve(column_lowest.size());
  for (const auto& [column, z] : column_lowest) lowest.push_back(z);
  const float f0 = geometry::kth_smallest(lowest, std::min(lowest.size() - 1, size_t(percentile * double(lowest.size()))));
  std::vector<float> band;
  for (const float z : heights)
    if (z >= f0 && z <= f0 + 0.06f) band.push_back(z);
  floor.z = geometry::median(band);
  for (auto& z : band) z = std::abs(z - floor.z);
  const float sigma = 1.4826f * geometry::median(band);
  floor.clear_z = floor.z + std::max(float(min_clearance), 4.f * sigma);
  return true;
}

Growth grow(const PointSet& seed, const LocalCloud& cloud, const Box& region, float min_z, const Owners& owned) {
  std::vector<uint32_t> touched;
  auto free_point = [&](uint32_t i) {
    if (cloud.points.xyz[i].z() < min_z) return false;
    const auto it = owned.find(point_key(cloud.points.scan[i], cloud.points.index[i]));
    if (it == owned.end()) return true;
    // Owned points come in runs of one object (the seed's own, mostly):
    // keep the list short before it is sorted.
    if (touched.empty() || touched.back() != it->second) touched.push_back(it->second);
    return false;
  };
  auto eligible = [&](uint32_t i) { return free_point(i) && region.contains(cloud.points.xyz[i]); };
  std::unordered_set<uint64_t> visited;
  std::deque<Eigen::Vector3i> queue;
  std::vector<uint32_t> added;
  size_t walked = 0, leaks = 0;
  auto visit = [&](const Eigen::Vector3i& v) {
    if (!visited.insert(voxel_key(v)).second) return;
    const auto [b, e] = cloud.in_voxel(v);
    bool any = false, outside = false;
    for (size_t k = b; k < e; ++k) {
      const uint32_t i = cloud.grid[k].second;
      if (eligible(i)) {
        added.push_back(i);
        any = true;
      } else if (!outside && free_point(i)) {
        outside = true;
      }
    }
    if (any) {
      queue.push_back(v);
      ++walked;
    } else if (outside) {
      ++leaks;  // each voxel is visited once
    }
  };
  // Seed voxels are walked from even when all their points are owned (they
  // are the object's own points): that is where the growth starts.
  for (const auto& p : seed.xyz) {
    const Eigen::Vector3i v = cloud.voxel_of(p);
    if (visited.count(voxel_key(v))) continue;
    visit(v);
    if (queue.empty() || queue.back() != v) queue.push_back(v);
  }
  while (!queue.empty()) {
    const Eigen::Vector3i v = queue.front();
    queue.pop_front();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (dx || dy || dz) visit(v + Eigen::Vector3i(dx, dy, dz));
  }
  std::sort(added.begin(), added.end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  return {std::move(added), walked, leaks, std::move(touched)};
}

HeldElsewhere::HeldElsewhere(const Box& floor_region, const std::vector<size_t>& neighbours,
                             const std::vector<LocalCloud>& clouds, const CompletionConfig& c) {
  if (neighbours.empty()) return;
  for (size_t n : neighbours) {
    Floor f;
    if (!local_floor(clouds[n], floor_region, c.floor_percentile, c.floor_clearance, f)) return;
    others.emplace_back(&clouds[n], f.clear_z);
  }
  valid = true;
}

std::vector<uint32_t> not_static(const std::vector<uint32_t>& add, const LocalCloud& cloud, const Box& floor_region,
                                 const std::vector<size_t>& neighbours, const std::vector<LocalCloud>& clouds,
                                 const CompletionConfig& c) {
  const HeldElsewhere held(floor_region, neighbours, clouds, c);
  if (!held.valid) return add;
  std::vector<uint32_t> keep;
  for (uint32_t i : add)
    if (!held.everywhere(cloud.voxel_of(cloud.points.xyz[i]))) keep.push_back(i);
  return keep;
}

}  // namespace lista::segment::completion
