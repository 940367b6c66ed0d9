#include "object_merges.hpp"

#include "growth_checks.hpp"

#include <algorithm>
#include <unordered_set>

namespace lista::segment::completion {

void drop_objects(ObjectSet& set, const std::vector<char>& gone) {
  std::vector<Object> kept;
  for (size_t k = 0; k < set.objects.size(); ++k)
    if (!gone[k]) kept.push_back(std::move(set.objects[k]));
  set.objects = std::move(kept);
  set.renumber();
}

size_t absorb_nested(ObjectSet& set, double share, float margin) {
  std::vector<size_t> order(set.objects.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return set.objects[a].points.size() < set.objects[b].points.size();
  });
  std::vector<char> gone(set.objects.size(), 0);
  size_t absorbed = 0;
  for (size_t k = 0; k < order.size(); ++k) {
    Object& small = set.objects[order[k]];
    if (small.points.empty()) continue;
    size_t into = set.objects.size();
    for (size_t j = k + 1; j < order.size(); ++j) {  // larger ones; the largest qualifying wins
      const Object& big = set.objects[order[j]];
      if (gone[order[j]] || big.mission != small.mission || big.points.size() <= small.points.size()) continue;
      const Box box = Box{big.bbox_min, big.bbox_max}.grown(margin, margin, margin);
      size_t inside = 0;
      for (const auto& p : small.points.xyz) inside += box.contains(p);
      if (double(inside) >= share * double(small.points.size())) into = order[j];
    }
    if (into == set.objects.size()) continue;
    Object& big = set.objects[into];
    big.points.append(small.points);
    big.update_geometry();
    small.points = PointSet();
    gone[order[k]] = 1;
    ++absorbed;
  }
  if (absorbed > 0) drop_objects(set, gone);
  return absorbed;
}

size_t join_connected(ObjectSet& set, const std::vector<std::tuple<float, size_t, size_t>>& candidates,
                      const std::vector<LocalCloud>& clouds, const std::vector<std::vector<size_t>>& neighbours,
                      const CompletionConfig& c, std::vector<std::string>& notes) {
  const size_t n = set.objects.size();
  std::vector<Owners> owned(clouds.size());
  for (size_t k = 0; k < n; ++k) {
    const Object& o = set.objects[k];
    for (size_t i = 0; i < o.points.size(); ++i) owned[o.mission][point_key(o.points.scan[i], o.points.index[i])] = uint32_t(k);
  }
  std::vector<size_t> parent(n);
  for (size_t k = 0; k < n; ++k) parent[k] = k;
  auto root = [&](size_t k) {
    while (parent[k] != k) k = parent[k] = parent[parent[k]];
    return k;
  };
  auto voxels = [](const PointSet& pts, const LocalCloud& cloud) {
    std::unordered_set<uint64_t> v;
    for (const auto& p : pts.xyz) v.insert(voxel_key(cloud.voxel_of(p)));
    return v;
  };
  // Whether a point of `pts` lies in or next to (26-neighbourhood) a voxel of `set_voxels`.
  auto next_to = [](const std::unordered_set<uint64_t>& set_voxels, const PointSet& pts, const LocalCloud& cloud) {
    for (const auto& p : pts.xyz) {
      const Eigen::Vector3i v = cloud.voxel_of(p);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz)
            if (set_voxels.count(voxel_key(v + Eigen::Vector3i(dx, dy, dz)))) return true;
    }
    return false;
  };
  const float margin = float(c.box_margin);
  for (const auto& [gap, i, j] : candidates) {
    if (root(i) == root(j)) continue;
    const Object &a = set.objects[i], &b = set.objects[j];
    const LocalCloud& cloud = clouds[a.mission];
    const std::string which = "objects " + std::to_string(a.id) + " and " + std::to_string(b.id);
    if (next_to(voxels(a.points, cloud), b.points, cloud)) {
      notes.push_back(which + ": not joined, their voxels touch (cut apart before)");
      continue;
    }
    Box own{a.bbox_min, a.bbox_max};
    own.extend(Box{b.bbox_min, b.bbox_max});
    const Box floor_region = own.grown(margin + 0.75f, 1.5f, margin);
    Floor f;
    if (!local_floor(cloud, floor_region, c.floor_percentile, c.floor_clearance, f)) continue;
    // No leak check: what connects two fragments (a table's top) reaches
    // past their boxes; what connects two unrelated objects (a wall, the
    // bench they stood on) is held elsewhere, which the test below sees.
    Box region = own.grown(margin, 0.f, margin);
    region.lo.z() = std::min(region.lo.z(), f.clear_z);
    const Growth g = grow(a.points, cloud, region, f.clear_z, owned[a.mission]);
    if (g.added.empty() || !std::binary_search(g.touched.begin(), g.touched.end(), uint32_t(j))) {
      notes.push_back(which + ": not joined, a growth from the first does not reach the second");
      continue;
    }
    const HeldElsewhere held(floor_region, neighbours[a.mission], clouds, c);
    if (!held.valid) {
      notes.push_back(which + ": not joined, a neighbouring mission has no floor there to compare with");
      continue;
    }
    size_t held_points = 0;
    for (uint32_t k : g.added) held_points += held.everywhere(cloud.voxel_of(cloud.points.xyz[k]));
    const double share = double(held_points) / double(g.added.size());
    if (share > 1.0 - c.static_share) {
      notes.push_back(which + ": not joined, connected over points held unchanged elsewhere (" + format_number(share) + ")");
      continue;
    }
    notes.push_back(which + ": joined, connected over " + std::to_string(g.added.size()) + " changed points (" +
                    format_number(share) + " held elsewhere)");
    parent[root(j)] = root(i);
  }
  // Each component into its largest member (the lowest index among equals).
  std::vector<size_t> into(n);
  for (size_t k = 0; k < n; ++k) into[k] = k;
  for (size_t k = 0; k < n; ++k) {
    const size_t r = root(k), best = into[r];
    const size_t size = set.objects[k].points.size(), best_size = set.objects[best].points.size();
    if (size > best_size || (size == best_size && k < best)) into[r] = k;
  }
  size_t joined = 0;
  std::vector<char> gone(n, 0);
  for (size_t k = 0; k < n; ++k) {
    const size_t target = into[root(k)];
    if (target == k) continue;
    set.objects[target].points.append(set.objects[k].points);
    set.objects[k].points = PointSet();
    gone[k] = 1;
    ++joined;
  }
  if (joined == 0) return 0;
  for (size_t k = 0; k < n; ++k)
    if (!gone[k]) set.objects[k].update_geometry();
  drop_objects(set, gone);
  return joined;
}

}  // namespace lista::segment::completion
