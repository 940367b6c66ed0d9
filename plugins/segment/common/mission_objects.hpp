// Header only, shared by the segment.* plugins (no plugin links another).
// Runs a per-mission clustering over every mission (in parallel, up to the
// stage's thread budget) and gathers the clusters into an ObjectSet: one
// Object per cluster per mission, ids 0..n-1 in mission then cluster order,
// so the result does not depend on the thread count.
#pragma once

#include <lista/context.hpp>
#include <lista/missions.hpp>
#include <lista/objects.hpp>

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <thread>
#include <vector>

namespace lista::seg {

using Clusters = std::vector<std::vector<uint32_t>>;

inline ObjectSet objects_from_missions(const MissionPoints& points, Context& context,
                                       const std::function<Clusters(const PointSet&, int threads)>& cluster) {
  const size_t m = points.sets.size();
  std::vector<Clusters> per_mission(m);
  const int workers = std::max(1, std::min<int>(context.threads(), int(m)));
  // Threads left over after one per mission go to the clustering itself.
  const int inner = std::max(1, context.threads() / std::max<int>(1, int(m)));
  std::atomic<size_t> next{0};
  std::vector<std::exception_ptr> errors(m);
  auto work = [&] {
    for (size_t i; (i = next++) < m;) {
      try {
        if (!context.cancelled()) per_mission[i] = cluster(points.sets[i], inner);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
  context.throw_if_cancelled();

  ObjectSet out;
  out.missions = points.missions;
  for (size_t i = 0; i < m; ++i)
    for (const auto& cluster_indices : per_mission[i]) {
      Object o;
      o.id = int(out.objects.size());
      o.mission = uint32_t(i);
      o.points = points.sets[i].select(cluster_indices);
      o.update_geometry();
      out.objects.push_back(std::move(o));
    }
  return out;
}

}  // namespace lista::seg
