// Header only, shared by the segment.* plugins (no plugin links another).
// Runs a per-mission clustering over every mission (in parallel, up to the
// stage's thread budget) and gathers the clusters into an ObjectSet: one
// Object per cluster per mission, ids 0..n-1 in mission then cluster order,
// so the result does not depend on the thread count. A cluster most of whose
// points its own mission also saw free (seen_free_in_own_mission) moved
// during the mission: it goes to ObjectSet::dynamics, not to the objects,
// with the clusters that stand mostly on its footprint.
#pragma once

#include <lista/context.hpp>
#include <lista/missions.hpp>
#include <lista/objects.hpp>
#include <lista/parallel.hpp>

#include <algorithm>
#include <functional>
#include <vector>

namespace lista::segmentation {

using Clusters = std::vector<std::vector<uint32_t>>;

inline ObjectSet objects_from_missions(const MissionPoints& points, Context& context,
                                       const std::function<Clusters(const PointSet&, int threads)>& cluster) {
  const size_t m = points.sets.size();
  std::vector<Clusters> per_mission(m);
  // Threads left over after one per mission go to the clustering itself.
  const int inner = std::max(1, context.threads() / std::max<int>(1, int(m)));
  parallel_for(m, context.threads(), [&](size_t i) {
    if (!context.cancelled()) per_mission[i] = cluster(points.sets[i], inner);
  });
  context.throw_if_cancelled();

  ObjectSet out;
  out.missions = points.missions;
  size_t dynamic_points = 0;
  for (size_t i = 0; i < m; ++i) {
    std::vector<Object> kept;
    const size_t first_dynamic = out.dynamics.size();
    for (const auto& cluster_indices : per_mission[i]) {
      Object o;
      o.mission = uint32_t(i);
      o.points = points.sets[i].select(cluster_indices);
      o.update_geometry();
      if (2 * o.points.seen_free_count() > o.points.size()) {
        out.dynamics.push_back({o.mission, uint32_t(o.points.size()), o.centroid, o.bbox_min, o.bbox_max});
        dynamic_points += o.points.size();
      } else {
        kept.push_back(std::move(o));
      }
    }
    // A piece of a moving thing that its scans happened not to see through
    // (a walker's torso above its seen-through legs) stands on the
    // thing's footprint: most of its points lie over a dynamic's xy box.
    // Nothing static of the mission can stand there, where something walked.
    for (Object& o : kept) {
      Dynamic* over = nullptr;
      for (size_t d = first_dynamic; d < out.dynamics.size() && !over; ++d) {
        const Dynamic& dyn = out.dynamics[d];
        size_t inside = 0;
        for (const auto& p : o.points.xyz)
          inside += p.x() >= dyn.bbox_min.x() && p.x() <= dyn.bbox_max.x() && p.y() >= dyn.bbox_min.y() &&
                    p.y() <= dyn.bbox_max.y();
        if (2 * inside > o.points.size()) over = &out.dynamics[d];
      }
      if (!over) {
        o.id = int(out.objects.size());
        out.objects.push_back(std::move(o));
        continue;
      }
      const float n0 = float(over->points), n1 = float(o.points.size());
      over->centroid = (n0 * over->centroid + n1 * o.centroid) / (n0 + n1);
      over->bbox_min = over->bbox_min.cwiseMin(o.bbox_min);
      over->bbox_max = over->bbox_max.cwiseMax(o.bbox_max);
      over->points += uint32_t(o.points.size());
      dynamic_points += o.points.size();
    }
  }
  context.record("dynamic_objects", double(out.dynamics.size()));
  context.record("dynamic_points", double(dynamic_points));
  if (!out.dynamics.empty())
    context.info(std::to_string(out.dynamics.size()) + " cluster(s) of " + std::to_string(dynamic_points) +
                 " points moved during their own mission (dynamic, not change); report.json lists them");
  return out;
}

}  // namespace lista::segmentation
