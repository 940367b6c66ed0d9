#include <lista_segmentation/voxel_clustering.hpp>

#include <lista/error.hpp>
#include <lista_geometry/union_find.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace lista::segmentation {
namespace {

using geometry::UnionFind;

// The 13 "forward" offsets of the 26-neighbourhood: visiting each voxel with
// these covers every adjacent pair once.
const std::vector<Eigen::Vector3i>& forward_offsets() {
  static const std::vector<Eigen::Vector3i> offsets = [] {
    std::vector<Eigen::Vector3i> v;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          Eigen::Vector3i d(dx, dy, dz);
          if (dx > 0 || (dx == 0 && dy > 0) || (dx == 0 && dy == 0 && dz > 0)) v.push_back(d);
        }
    return v;
  }();
  return offsets;
}

}  // namespace

std::vector<std::vector<uint32_t>> cluster_voxels(const std::vector<Eigen::Vector3f>& xyz,
                                                  const VoxelClusterConfig& config) {
  if (!(config.tolerance > 0)) throw Error("cluster tolerance must be > 0");
  const size_t n = xyz.size();
  if (n == 0) return {};
  const double inv = 1.0 / config.tolerance;

  // Points grouped by voxel: sort point indices by voxel key.
  std::vector<uint64_t> key(n);
  std::vector<Eigen::Vector3i> cell(n);
  for (size_t i = 0; i < n; ++i) {
    cell[i] = geometry::voxel_in_reach(xyz[i], inv, i);
    key[i] = geometry::voxel_key(cell[i]);
  }
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return key[a] != key[b] ? key[a] < key[b] : a < b; });
  std::vector<uint32_t> start;  // voxel v owns order[start[v] .. start[v+1])
  std::unordered_map<uint64_t, uint32_t> voxel_of_key;
  for (size_t k = 0; k < n; ++k)
    if (k == 0 || key[order[k]] != key[order[k - 1]]) {
      voxel_of_key.emplace(key[order[k]], uint32_t(start.size()));
      start.push_back(uint32_t(k));
    }
  const size_t voxels = start.size();
  start.push_back(uint32_t(n));

  auto neighbour = [&](uint32_t v, const Eigen::Vector3i& d) -> int64_t {
    const Eigen::Vector3i c = cell[order[start[v]]] + d;
    auto it = voxel_of_key.find(geometry::voxel_key(c));
    return it == voxel_of_key.end() ? -1 : int64_t(it->second);
  };

  std::vector<uint32_t> root_of_point(n);
  if (!config.exact) {
    UnionFind uf(voxels);
    for (uint32_t v = 0; v < voxels; ++v)
      for (const auto& d : forward_offsets()) {
        int64_t w = neighbour(v, d);
        if (w >= 0) uf.unite(v, uint32_t(w));
      }
    for (uint32_t v = 0; v < voxels; ++v)
      for (uint32_t k = start[v]; k < start[v + 1]; ++k) root_of_point[order[k]] = uf.find(v);
  } else {
    // Union-find over points; a pair is tested only if not already joined.
    UnionFind uf(n);
    const float tol2 = float(config.tolerance * config.tolerance);
    auto join_lists = [&](uint32_t v, uint32_t w, bool same) {
      for (uint32_t a = start[v]; a < start[v + 1]; ++a) {
        const uint32_t i = order[a];
        for (uint32_t b = same ? a + 1 : start[w]; b < start[w + 1]; ++b) {
          const uint32_t j = order[b];
          if ((xyz[i] - xyz[j]).squaredNorm() <= tol2 && uf.find(i) != uf.find(j)) uf.unite(i, j);
        }
      }
    };
    for (uint32_t v = 0; v < voxels; ++v) {
      join_lists(v, v, true);
      for (const auto& d : forward_offsets()) {
        int64_t w = neighbour(v, d);
        if (w >= 0) join_lists(v, uint32_t(w), false);
      }
    }
    for (uint32_t i = 0; i < n; ++i) root_of_point[i] = uf.find(i);
  }

  // Gather clusters in order of their smallest point index.
  std::unordered_map<uint32_t, uint32_t> cluster_of_root;
  std::vector<std::vector<uint32_t>> clusters;
  for (uint32_t i = 0; i < n; ++i) {
    auto [it, added] = cluster_of_root.emplace(root_of_point[i], uint32_t(clusters.size()));
    if (added) clusters.emplace_back();
    clusters[it->second].push_back(i);
  }
  clusters.erase(std::remove_if(clusters.begin(), clusters.end(),
                                [&](const std::vector<uint32_t>& c) {
                                  return c.size() < config.min_points || c.size() > config.max_points;
                                }),
                 clusters.end());
  return clusters;
}

}  // namespace lista::segmentation
