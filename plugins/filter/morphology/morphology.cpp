#include "morphology.hpp"

#include <lista/error.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace lista::filter {
namespace {

template <class F>
void for_neighbours(uint64_t k, F&& f) {
  const Eigen::Vector3i c = geometry::voxel_of_key(k);
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz)
        if (dx || dy || dz) f(geometry::voxel_key(c + Eigen::Vector3i(dx, dy, dz)));
}

}  // namespace

std::vector<uint32_t> morphology_keep(const PointSet& points, const MorphologyConfig& c) {
  if (!(c.voxel > 0)) throw Error("voxel must be > 0");
  const double inv = 1.0 / c.voxel;
  std::vector<uint64_t> key(points.size());
  std::unordered_set<uint64_t> occupied;
  for (size_t i = 0; i < points.size(); ++i) {
    key[i] = geometry::voxel_key(geometry::voxel_in_reach(points.xyz[i], inv, i));
    occupied.insert(key[i]);
  }
  // Erosion (rank filter over the 26-neighbourhood).
  std::unordered_set<uint64_t> kept;
  for (uint64_t k : occupied) {
    int n = 0;
    for_neighbours(k, [&](uint64_t q) { n += int(occupied.count(q)); });
    if (n >= c.min_neighbours) kept.insert(k);
  }
  if (c.reconstruct) {
    // Opening by reconstruction: grow from the surviving cores through
    // occupied voxels until nothing changes, so every part connected to a
    // core (thin legs, shelf boards, a table top's edge) comes back whole,
    // while components without a core (noise, lone slivers) stay gone.
    std::vector<uint64_t> frontier(kept.begin(), kept.end());
    while (!frontier.empty()) {
      const uint64_t k = frontier.back();
      frontier.pop_back();
      for_neighbours(k, [&](uint64_t q) {
        if (occupied.count(q) && kept.insert(q).second) frontier.push_back(q);
      });
    }
  }
  // Dilation, only onto voxels that were occupied.
  for (int step = 0; !c.reconstruct && step < c.dilate_steps; ++step) {
    std::vector<uint64_t> grow;
    for (uint64_t k : kept)
      for_neighbours(k, [&](uint64_t q) {
        if (occupied.count(q) && !kept.count(q)) grow.push_back(q);
      });
    if (grow.empty()) break;
    kept.insert(grow.begin(), grow.end());
  }
  std::vector<uint32_t> keep;
  for (uint32_t i = 0; i < points.size(); ++i)
    if (kept.count(key[i])) keep.push_back(i);
  return keep;
}

}  // namespace lista::filter
