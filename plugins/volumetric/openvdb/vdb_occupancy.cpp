// How the map is built, and why it is fast:
//  - scans are shared out to threads (dynamic); each thread owns an Int64Grid
//    of packed per-voxel counters, so ray casting never locks;
//  - a counter packs (last scan stamp | hits | misses): within a scan, hits are
//    applied first and every voxel is counted at most once (the stamp), so one
//    scan gives a voxel at most one hit or one miss and a hit wins over a miss
//    in the same scan (OctoMap's computeUpdate rule) without any per-scan set;
//  - the DDA writes through a cached leaf pointer (8^3 voxels), falling back to
//    a ValueAccessor only on leaf changes;
//  - thread grids merge by adding counts leaf by leaf, then log-odds =
//    clamp(hits*l_hit + misses*l_miss). Integer counts make the result
//    independent of thread count and scheduling. Unlike OctoMap, clamping is
//    applied once at the end instead of after each scan; the two differ only
//    for voxels whose state flipped within one mission.
#include "vdb_occupancy.hpp"

#include <lista_raycast/dda.hpp>

#include <openvdb/openvdb.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <thread>

namespace lista::volumetric {

namespace {

using namespace lista::raycast;
using Int64Leaf = openvdb::Int64Tree::LeafNodeType;

constexpr int kHitShift = 22, kStampShift = 44;
constexpr int64_t kCountMask = (int64_t(1) << 22) - 1;
constexpr int64_t kMaxScans = (int64_t(1) << 19) - 2;  // stamp = scan + 1 must fit in 19 bits

inline int64_t stamp_of(int64_t v) { return v >> kStampShift; }
inline int64_t hits_of(int64_t v) { return (v >> kHitShift) & kCountMask; }
inline int64_t misses_of(int64_t v) { return v & kCountMask; }

// Per-thread writer: caches the current leaf so consecutive DDA steps inside
// one 8^3 block cost an array access.
class CounterWriter {
 public:
  explicit CounterWriter(openvdb::Int64Grid& grid) : acc_(grid.getAccessor()) {}

  // Counts one hit (hit=true) or miss for `scan_stamp`, once per scan.
  inline void touch(const Voxel& v, int64_t scan_stamp, bool hit) {
    const openvdb::Coord c(v.x(), v.y(), v.z());
    const openvdb::Coord origin = c & ~(Int64Leaf::DIM - 1);
    if (!leaf_ || origin != leaf_origin_) {
      leaf_ = acc_.touchLeaf(c);
      leaf_origin_ = origin;
    }
    const openvdb::Index off = Int64Leaf::coordToOffset(c);
    const int64_t cur = leaf_->getValue(off);
    if (stamp_of(cur) == scan_stamp) return;  // already counted in this scan
    const int64_t counts = cur & ((int64_t(1) << kStampShift) - 1);
    leaf_->setValueOn(off, (scan_stamp << kStampShift) | (counts + (hit ? (int64_t(1) << kHitShift) : 1)));
  }

 private:
  openvdb::Int64Grid::Accessor acc_;
  Int64Leaf* leaf_ = nullptr;
  openvdb::Coord leaf_origin_;
};

struct ThreadWork {
  openvdb::Int64Grid::Ptr grid = openvdb::Int64Grid::create(0);
  uint64_t rays = 0, visits = 0;
};

void cast_scan(const Mission& mission, size_t i, const VolumetricConfig& c, CounterWriter& w,
               ThreadWork& work, std::vector<Eigen::Vector3d>& ends, std::vector<char>& is_hit) {
  const PointSet& pts = *mission.scans[i].points;
  const double inv_res = 1.0 / c.resolution;
  const double max_range = c.max_range > 0 ? c.max_range * inv_res : 0.0;
  const double margin = c.hit_margin * inv_res;
  const Eigen::Affine3d to_index = Eigen::Scaling(inv_res) * mission.sensor_to_common(i);
  const Eigen::Vector3d origin = to_index.translation();
  const int64_t stamp = static_cast<int64_t>(i) + 1;
  ends.resize(pts.size());
  is_hit.resize(pts.size());
  // Hits first, so that a voxel holding a return is never counted free in the same scan.
  for (size_t j = 0; j < pts.size(); ++j) {
    ends[j] = to_index * pts.xyz[j].cast<double>();
    is_hit[j] = clip_ray(origin, ends[j], max_range);
    if (is_hit[j]) w.touch(voxel_of(ends[j]), stamp, true);
  }
  uint64_t visits = 0;
  for (size_t j = 0; j < pts.size(); ++j)
    visits += walk_ray(origin, is_hit[j] ? free_end(origin, ends[j], margin) : ends[j],
                       [&](const Voxel& v) { w.touch(v, stamp, false); });
  work.rays += pts.size();
  work.visits += visits;
}

// Adds the counts of `src` into `dst` (stamps dropped).
void merge_counts(openvdb::Int64Grid& dst, const openvdb::Int64Grid& src) {
  auto acc = dst.getAccessor();
  constexpr int64_t counts_mask = (int64_t(1) << kStampShift) - 1;
  for (auto leaf = src.tree().cbeginLeaf(); leaf; ++leaf) {
    Int64Leaf* d = acc.touchLeaf(leaf->origin());
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      const openvdb::Index off = it.pos();
      d->setValueOn(off, (d->getValue(off) & counts_mask) + (*it & counts_mask));
    }
  }
}

class VdbReader : public OccupancyReader {
 public:
  explicit VdbReader(const openvdb::FloatGrid& g) : acc_(g.getConstAccessor()) {}
  bool logodds(const Voxel& v, float& out) override {
    const openvdb::Coord c(v.x(), v.y(), v.z());
    return acc_.probeValue(c, out);
  }

 private:
  openvdb::FloatGrid::ConstAccessor acc_;
};

class VdbMap : public OccupancyMap {
 public:
  explicit VdbMap(openvdb::FloatGrid::Ptr g) : grid_(std::move(g)) {}
  std::unique_ptr<OccupancyReader> reader() const override { return std::make_unique<VdbReader>(*grid_); }

 private:
  openvdb::FloatGrid::Ptr grid_;
};

}  // namespace

std::unique_ptr<OccupancyMap> build_vdb_map(const Mission& mission, const VolumetricConfig& c,
                                            int threads, MapStats& stats, Progress* progress) {
  static std::once_flag init;
  std::call_once(init, [] { openvdb::initialize(); });
  if (static_cast<int64_t>(mission.scans.size()) > kMaxScans)
    throw Error("mission '" + mission.name + "' has more than " + std::to_string(kMaxScans) +
                " scans; split it");

  const int n_threads = std::max(1, std::min<int>(threads, static_cast<int>(mission.scans.size())));
  std::vector<ThreadWork> work(n_threads);
  std::atomic<size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&](int t) {
    try {
      CounterWriter writer(*work[t].grid);
      std::vector<Eigen::Vector3d> ends;
      std::vector<char> is_hit;
      for (size_t i; (i = next.fetch_add(1)) < mission.scans.size();) {
        cast_scan(mission, i, c, writer, work[t], ends, is_hit);
        if (progress) progress->advance(1);
      }
    } catch (...) {
      std::lock_guard<std::mutex> lock(failure_mutex);
      failure = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < n_threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (auto& th : pool) th.join();
  if (failure) std::rethrow_exception(failure);

  for (int t = 1; t < n_threads; ++t) {
    merge_counts(*work[0].grid, *work[t].grid);
    work[t].grid.reset();
  }

  // Counts -> clamped log-odds.
  const float l_hit = logodds(c.prob_hit), l_miss = logodds(c.prob_miss);
  const float l_min = logodds(c.clamping_min), l_max = logodds(c.clamping_max);
  const float l_occ = logodds(c.occupied_threshold);
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setTransform(openvdb::math::Transform::createLinearTransform(c.resolution));
  grid->setName(mission.name);
  auto out = grid->getAccessor();
  stats = MapStats{};
  for (auto leaf = work[0].grid->tree().cbeginLeaf(); leaf; ++leaf) {
    auto* d = out.touchLeaf(leaf->origin());
    for (auto it = leaf->cbeginValueOn(); it; ++it) {
      const float l = std::clamp(hits_of(*it) * l_hit + misses_of(*it) * l_miss, l_min, l_max);
      d->setValueOn(it.pos(), l);
      if (l > l_occ) ++stats.occupied_voxels;
      else ++stats.free_voxels;
    }
  }
  for (const auto& w : work) {
    stats.rays += w.rays;
    stats.voxel_visits += w.visits;
  }
  return std::make_unique<VdbMap>(grid);
}

}  // namespace lista::volumetric
