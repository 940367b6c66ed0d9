// Per scan: every thread casts a share of the beams with computeRayKeys into
// its own KeySets (hits, free); the sets are merged, free keys that also hold
// a return in this scan are dropped (a hit wins, as in OcTree::computeUpdate),
// then the tree is updated serially (OcTree is not thread-safe for writes),
// free cells first, then hits. Inner nodes are updated once at the end
// (lazy evaluation) instead of after every voxel.
#include "octree_occupancy.hpp"

#include <lista_raycast/dda.hpp>

#include <octomap/OcTree.h>
#include <omp.h>

#include <algorithm>

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

  for (size_t i = 0; i < mission.scans.size(); ++i) {
    const PointSet& pts = *mission.scans[i].points;
    const Eigen::Isometry3d pose = mission.sensor_to_common(i);
    const Eigen::Vector3d o = pose.translation();
    const octomap::point3d origin(static_cast<float>(o.x()), static_cast<float>(o.y()), static_cast<float>(o.z()));
    bool out_of_bounds = false;
#pragma omp parallel num_threads(n_threads) reduction(+ : visits) reduction(|| : out_of_bounds)
    {
      const int t = omp_get_thread_num();
      hits[t].clear();
      frees[t].clear();
#pragma omp for schedule(static)
      for (long j = 0; j < static_cast<long>(pts.size()); ++j) {
        Eigen::Vector3d e = pose * pts.xyz[j].cast<double>();
        const bool hit = clip_ray(o, e, c.max_range);
        const Eigen::Vector3d f =
            hit ? free_end(o, e, beam_margin(o, e, c.hit_margin, c.graze_height, c.graze_max)) : e;
        const octomap::point3d end(static_cast<float>(e.x()), static_cast<float>(e.y()), static_cast<float>(e.z()));
        const octomap::point3d free_to(static_cast<float>(f.x()), static_cast<float>(f.y()), static_cast<float>(f.z()));
        if (!tree->computeRayKeys(origin, free_to, rays[t])) {
          out_of_bounds = true;
          continue;
        }
        visits += rays[t].size();
        frees[t].insert(rays[t].begin(), rays[t].end());
        if (hit) hits[t].insert(tree->coordToKey(end));
      }
    }
    if (out_of_bounds)
      throw Error("mission '" + mission.name + "', scan " + std::to_string(i) +
                  ": points beyond the octree's extent; check the poses and the resolution");
    for (int t = 1; t < n_threads; ++t) {
      hits[0].insert(hits[t].begin(), hits[t].end());
      frees[0].insert(frees[t].begin(), frees[t].end());
    }
    for (const auto& k : frees[0])
      if (!hits[0].count(k)) tree->updateNode(k, false, true);
    for (const auto& k : hits[0]) tree->updateNode(k, true, true);
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
