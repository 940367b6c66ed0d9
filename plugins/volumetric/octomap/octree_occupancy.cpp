// Per scan: every thread casts a share of the beams with computeRayKeys into
// its own KeySets (hits, free); the sets are merged, free keys that also hold
// a return in this scan are dropped (a hit wins, as in OcTree::computeUpdate),
// then the tree is updated serially (OcTree is not thread-safe for writes),
// free cells first, then hits. Inner nodes are updated once at the end
// (lazy evaluation) instead of after every voxel. The key sets and the tree
// are charged to a MemoryBudget after each scan, so a map outgrowing the
// memory stops with a clear error; an allocation failing inside a scan (an
// exception may not leave an OpenMP region) is turned into the same error.
#include "octree_occupancy.hpp"

#include <lista_raycast/dda.hpp>
#include <lista_raycast/memory_budget.hpp>

#include <octomap/OcTree.h>
#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <new>

namespace lista::volumetric {

namespace {

using namespace lista::raycast;

class OctreeReader : public OccupancyReader {
 public:
  explicit OctreeReader(const octomap::OcTree& t) : tree_(t) {}
  bool logodds(const Voxel& v, float& out) override {
    constexpr int half = 32768;  // OctoMap's tree_max_val at depth 16
    if (v.x() < -half || v.x() >= half || v.y() < -half || v.y() >= half || v.z() < -half ||
        v.z() >= half)
      return false;
    const octomap::OcTreeKey key(static_cast<uint16_t>(v.x() + half), static_cast<uint16_t>(v.y() + half),
                                 static_cast<uint16_t>(v.z() + half));
    const octomap::OcTreeNode* node = tree_.search(key);
    if (!node) return false;
    out = node->getLogOdds();
    return true;
  }

 private:
  const octomap::OcTree& tree_;
};

class OctreeMap : public OccupancyMap {
 public:
  explicit OctreeMap(std::unique_ptr<octomap::OcTree> t) : tree_(std::move(t)) {}
  std::unique_ptr<OccupancyReader> reader() const override { return std::make_unique<OctreeReader>(*tree_); }

 private:
  std::unique_ptr<octomap::OcTree> tree_;
};

}  // namespace

std::unique_ptr<OccupancyMap> build_octree_map(const Mission& mission, const VolumetricConfig& c,
                                               int threads, MapStats& stats, Progress* progress) {
  auto tree = std::make_unique<octomap::OcTree>(c.resolution);
  tree->setProbHit(c.prob_hit);
  tree->setProbMiss(c.prob_miss);
  tree->setClampingThresMin(c.clamping_min);
  tree->setClampingThresMax(c.clamping_max);
  tree->setOccupancyThres(c.occupied_threshold);
  const int n_threads = std::max(1, threads);
  std::vector<octomap::KeySet> hits(n_threads), frees(n_threads);
  std::vector<octomap::KeyRay> rays(n_threads);
  stats = MapStats{};
  uint64_t visits = 0;
  // Three quarters of what is free now, as volumetric.openvdb allows itself.
  const uint64_t limit = raycast::memory_available_bytes() / 4 * 3;
  auto too_big = [&] {
    char text[300];
    std::snprintf(text, sizeof text,
                  "mission '%s': its occupancy map outgrows the %.1f GiB of memory free at resolution %g m "
                  "(max_range %g m); set a coarser resolution or a smaller max_range",
                  mission.name.c_str(), double(limit) / double(1ull << 30), c.resolution, c.max_range);
    return Error(text);
  };
  // Bytes per key held in a KeySet (an unordered_set node and its bucket)
  // and per tree node (the node and its share of a children array).
  constexpr uint64_t kKeyBytes = 48, kNodeBytes = 80;

  for (size_t i = 0; i < mission.scans.size(); ++i) {
    const PointSet& pts = *mission.scans[i].points;
    const Eigen::Isometry3d pose = mission.sensor_to_common(i);
    const Eigen::Vector3d o = pose.translation();
    const octomap::point3d origin(static_cast<float>(o.x()), static_cast<float>(o.y()), static_cast<float>(o.z()));
    bool out_of_bounds = false, out_of_memory = false;
#pragma omp parallel num_threads(n_threads) reduction(+ : visits) reduction(|| : out_of_bounds, out_of_memory)
    {
      const int t = omp_get_thread_num();
      hits[t].clear();
      frees[t].clear();
      // One beam's keys; false if it leaves the octree.
      auto cast_beam = [&](long j) {
        Eigen::Vector3d e = pose * pts.xyz[j].cast<double>();
        const bool hit = clip_ray(o, e, c.max_range);
        const Eigen::Vector3d f =
            hit ? free_end(o, e, beam_margin(o, e, c.hit_margin, c.graze_height, c.graze_max)) : e;
        const octomap::point3d end(static_cast<float>(e.x()), static_cast<float>(e.y()), static_cast<float>(e.z()));
        const octomap::point3d free_to(static_cast<float>(f.x()), static_cast<float>(f.y()), static_cast<float>(f.z()));
        if (!tree->computeRayKeys(origin, free_to, rays[t])) return false;
        visits += rays[t].size();
        frees[t].insert(rays[t].begin(), rays[t].end());
        if (hit) hits[t].insert(tree->coordToKey(end));
        return true;
      };
#pragma omp for schedule(static)
      for (long j = 0; j < static_cast<long>(pts.size()); ++j) {
        if (out_of_memory) continue;
        try {
          if (!cast_beam(j)) out_of_bounds = true;
        } catch (const std::bad_alloc&) {
          out_of_memory = true;
        }
      }
    }
    if (out_of_memory) throw too_big();
    if (out_of_bounds)
      throw Error("mission '" + mission.name + "', scan " + std::to_string(i) +
                  ": points beyond the octree's extent; check the poses and the resolution");
    try {
      uint64_t keys = 0;
      for (int t = 0; t < n_threads; ++t) keys += hits[t].size() + frees[t].size();
      if (keys * kKeyBytes + uint64_t(tree->size()) * kNodeBytes > limit) throw too_big();
      for (int t = 1; t < n_threads; ++t) {
        hits[0].insert(hits[t].begin(), hits[t].end());
        frees[0].insert(frees[t].begin(), frees[t].end());
      }
      for (const auto& k : frees[0])
        if (!hits[0].count(k)) tree->updateNode(k, false, true);
      for (const auto& k : hits[0]) tree->updateNode(k, true, true);
      if (uint64_t(tree->size()) * kNodeBytes > limit) throw too_big();
    } catch (const std::bad_alloc&) {
      throw too_big();
    }
    stats.rays += pts.size();
    if (progress) progress->advance(1);
  }
  tree->updateInnerOccupancy();
  stats.voxel_visits = visits;
  stats.voxels_walked = visits;
  for (auto it = tree->begin_leafs(), end = tree->end_leafs(); it != end; ++it) {
    if (tree->isNodeOccupied(*it)) ++stats.occupied_voxels;
    else ++stats.free_voxels;
  }
  return std::make_unique<OctreeMap>(std::move(tree));
}

}  // namespace lista::volumetric
