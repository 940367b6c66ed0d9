#include "completion_pass.hpp"

#include "growth_checks.hpp"
#include "object_merges.hpp"

#include <lista_geometry/object_geometry.hpp>
#include <lista/parallel.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace lista::segment::completion {

using geometry::box_gap;

CompletionPass::CompletionPass(ObjectSet& objects, std::vector<const Mission*> mission_of, const CompletionConfig& c)
    : out_(objects),
      mission_of_(std::move(mission_of)),
      c_(c),
      margin_(float(c.box_margin)),
      nm_(objects.missions.size()),
      clouds_(nm_) {}

Box CompletionPass::own_floor_region(const Object& o) const {
  return Box{o.bbox_min, o.bbox_max}.grown(margin_ + 0.75f, 1.5f, margin_);
}

std::vector<std::optional<Floor>> CompletionPass::own_floors(const std::function<bool(const Object&)>& wanted) const {
  std::vector<std::optional<Floor>> floors(out_.objects.size());
  parallel_for(floors.size(), c_.threads, [&](size_t k) {
    const Object& o = out_.objects[k];
    Floor f;
    if (!o.points.empty() && wanted(o) &&
        local_floor(clouds_[o.mission], own_floor_region(o), c_.floor_percentile, c_.floor_clearance, f))
      floors[k] = f;
  });
  return floors;
}

Box CompletionPass::pair_region(const Object& a, const Object& b) {
  Box r;
  for (const Object* o : {&a, &b}) r.extend(Box{o->bbox_min, o->bbox_max});
  return r;
}

// Boxes that overlap are all 0 m apart, and gaps under one growth voxel are
// all "touching" to the growth; among those the nearer centroids
// (horizontal) come first, so a short move's two slivers go before a
// neighbour whose box merely reaches into theirs.
std::vector<std::tuple<float, float, float, size_t, size_t>> CompletionPass::candidate_pairs() const {
  std::vector<std::tuple<float, float, float, size_t, size_t>> candidates;
  for (size_t i = 0; i < out_.objects.size(); ++i)
    for (size_t j = 0; j < out_.objects.size(); ++j) {
      const Object &a = out_.objects[i], &b = out_.objects[j];
      if (b.mission != a.mission + 1 || a.points.empty() || b.points.empty()) continue;
      const float gap = box_gap(a, b);
      if (gap > c_.pair_gap) continue;
      if (c_.pair_order == PairOrder::centroid)
        candidates.emplace_back(std::floor(gap / float(c_.voxel)), (a.centroid - b.centroid).head<2>().norm(), gap, i, j);
      else
        candidates.emplace_back(gap, 0.f, 0.f, i, j);
    }
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

std::vector<std::tuple<float, size_t, size_t>> CompletionPass::connected_candidates(
    const std::vector<char>& paired) const {
  std::vector<std::tuple<float, size_t, size_t>> candidates;
  for (size_t i = 0; i < out_.objects.size(); ++i)
    for (size_t j = i + 1; j < out_.objects.size(); ++j) {
      const Object &a = out_.objects[i], &b = out_.objects[j];
      if (a.mission != b.mission || a.points.empty() || b.points.empty()) continue;
      if (!paired.empty() && (paired[i] || paired[j])) continue;
      const float gap = box_gap(a, b);
      if (gap <= c_.pair_gap) candidates.emplace_back(gap, i, j);
    }
  std::sort(candidates.begin(), candidates.end());
  return candidates;
}

std::vector<size_t> CompletionPass::neighbours(size_t m) const {
  std::vector<size_t> n;
  if (m > 0) n.push_back(m - 1);
  if (m + 1 < nm_) n.push_back(m + 1);
  return n;
}

// Every object's own region: its floor is measured (rules 0 and 7)
// whether or not it self-completes.
void CompletionPass::add_own_regions(std::vector<std::vector<Box>>& regions, bool with_neighbours) const {
  for (const auto& o : out_.objects) {
    if (o.points.empty()) continue;
    regions[o.mission].push_back(own_floor_region(o));
    if (with_neighbours)
      for (size_t n : neighbours(o.mission)) regions[n].push_back(own_floor_region(o));
  }
}

// Rule 4b grows in the union of two boxes of one mission and asks the
// neighbouring missions what they hold there.
void CompletionPass::add_connected_regions(std::vector<std::vector<Box>>& regions) const {
  if (!c_.join_connected) return;
  for (const auto& [gap, i, j] : connected_candidates({})) {
    const Object &a = out_.objects[i], &b = out_.objects[j];
    const Box r = pair_region(a, b).grown(margin_ + 0.75f, 1.5f, margin_);
    regions[a.mission].push_back(r);
    for (size_t n : neighbours(a.mission)) regions[n].push_back(r);
  }
}

void CompletionPass::gather_clouds() {
  std::vector<std::vector<Box>> regions(nm_);
  for (const auto& [order, apart, gap, i, j] : candidate_pairs()) {
    const Box r = pair_region(out_.objects[i], out_.objects[j]).grown(margin_ + 0.75f, 1.5f, margin_);
    regions[out_.objects[i].mission].push_back(r);
    regions[out_.objects[j].mission].push_back(r);
  }
  add_own_regions(regions, (c_.self_complete && c_.static_check) || c_.thin_height > 0.0);
  add_connected_regions(regions);
  // The missions side by side: sorting a cloud's voxel index is serial.
  const int each = std::max(1, c_.threads / int(nm_));
  parallel_for(nm_, c_.threads, [&](size_t m) { clouds_[m] = gather(*mission_of_[m], regions[m], float(c_.voxel), each); });
}

// The floor itself is no object: a cluster lying (floor_share of its
// points) within the floor clearance of its local floor, at most
// kFloorObjectHeight, is ground the difference flagged (grazing beams,
// uneven ground between scans), never a thing that moved. Dropped before
// pairing so it pairs with nothing.
void CompletionPass::drop_floor_objects() {
  if (c_.floor_share <= 0.0) return;
  std::vector<Object> kept;
  const std::vector<std::optional<Floor>> floors = own_floors([](const Object&) { return true; });
  for (size_t k = 0; k < out_.objects.size(); ++k) {
    Object& o = out_.objects[k];
    if (const auto& f = floors[k]) {
      const float top = std::min(f->clear_z, f->z + kFloorObjectHeight);
      size_t low = 0;
      for (const auto& p : o.points.xyz) low += p.z() < top;
      if (double(low) >= c_.floor_share * double(o.points.size())) {
        ++st_.floor_only;
        continue;
      }
    }
    kept.push_back(std::move(o));
  }
  out_.objects = std::move(kept);
}

// A thin cluster (under thin_height tall) whose voxels every neighbouring
// mission also holds is a horizontal surface that did not change (a table
// top grazed by beams); a thin object that did change (a cart's deck seen
// from above) is not held where it was. Nor is a patch of a surface the
// other mission's beams grazed without hitting (a sparse scanner, a rack's
// low shelf): its own mission continues the surface on thin_surface_sides
// of its four sides.
void CompletionPass::drop_thin_surfaces() {
  if (c_.thin_height > 0.0) {
    std::vector<Object> kept;
    for (auto& o : out_.objects) {
      if (!o.points.empty() && o.bbox_max.z() - o.bbox_min.z() < float(c_.thin_height)) {
        const HeldElsewhere held(own_floor_region(o), neighbours(o.mission), clouds_, c_);
        if (held.valid) {
          size_t n = 0;
          for (const auto& p : o.points.xyz) n += held.everywhere(clouds_[o.mission].voxel_of(p));
          if (double(n) >= c_.static_share * double(o.points.size())) {
            ++st_.thin_static;
            continue;
          }
        }
        if (c_.thin_surface_sides > 0 &&
            surface_sides(o, clouds_[o.mission], margin_, kSurfaceNoise) >= c_.thin_surface_sides) {
          ++st_.thin_surface;
          continue;
        }
      }
      kept.push_back(std::move(o));
    }
    out_.objects = std::move(kept);
  }
  if (st_.floor_only || st_.thin_static || st_.thin_surface) out_.renumber();
}

// Nearest first, each object in at most one completed pair. With
// pair_retry, a pair whose growth is refused frees both objects for their
// next-nearest candidates (two slivers of one short move whose boxes touch
// a third object's as closely: the first candidate may be the wrong one).
std::vector<Pair> CompletionPass::candidate_pairs_to_try() const {
  std::vector<Pair> pairs;
  std::vector<char> used(out_.objects.size(), 0);
  for (const auto& [order, apart, gap, i, j] : candidate_pairs()) {
    if (!c_.pair_retry) {
      if (used[i] || used[j]) continue;
      used[i] = used[j] = 1;
    }
    const Box r = pair_region(out_.objects[i], out_.objects[j]);
    // Down to the floor: the region's lower bound is set once the floor is known.
    pairs.push_back({i, j, r, r.grown(margin_, 0.f, margin_), r.grown(margin_ + 0.75f, 1.5f, margin_)});
  }
  return pairs;
}

// A dropped object's points need not stay. The leak check looks one voxel
// past a region, well inside its gathered floor region.
void CompletionPass::narrow_clouds(const std::vector<Pair>& pairs) {
  std::vector<std::vector<Box>> regions(nm_);
  for (const auto& p : pairs)
    for (size_t k : {p.a, p.b}) regions[out_.objects[k].mission].push_back(p.floor_region);
  add_own_regions(regions, c_.self_complete && c_.static_check);
  add_connected_regions(regions);
  parallel_for(nm_, c_.threads, [&](size_t m) { clouds_[m] = restrict_to(clouds_[m], regions[m]); });
  owned_.assign(nm_, {});
  for (size_t k = 0; k < out_.objects.size(); ++k) {
    const Object& o = out_.objects[k];
    for (size_t i = 0; i < o.points.size(); ++i)
      owned_[o.mission][point_key(o.points.scan[i], o.points.index[i])] = uint32_t(k);
  }
}

// Free objects of one mission connected over changed points are one object
// the difference cut apart (a table's legs without its top).
void CompletionPass::join_connected_objects(const std::vector<char>& paired) {
  if (!c_.join_connected) return;
  std::vector<std::vector<size_t>> neighbour_lists(nm_);
  for (size_t m = 0; m < nm_; ++m) neighbour_lists[m] = neighbours(m);
  st_.connected = join_connected(out_, connected_candidates(paired), clouds_, neighbour_lists, c_, st_.object_notes);
}

// Every object: its own missing points inside its box grown by box_margin
// (mostly its base next to the floor, and surfaces the difference left out
// next to others), or only its base when the growth wants out of the box
// (the object touches a wall or other furniture).
void CompletionPass::self_complete() {
  if (!c_.self_complete) return;
  // Each object's floor is of its box before it grows: measured up front.
  const std::vector<std::optional<Floor>> floors = own_floors([](const Object&) { return true; });
  for (size_t k = 0; k < out_.objects.size(); ++k) {
    Object& o = out_.objects[k];
    if (!floors[k]) continue;
    const LocalCloud& cloud = clouds_[o.mission];
    const Floor& f = *floors[k];
    Box r = Box{o.bbox_min, o.bbox_max}.grown(margin_, margin_, margin_);
    const bool on_floor = o.bbox_min.z() - f.z <= kOnFloorGap;
    if (on_floor) r.lo.z() = f.clear_z;
    const Growth g = grow(o.points, cloud, r, f.clear_z, owned_[o.mission]);
    std::vector<uint32_t> add;
    std::string how;
    if (g.contained(c_.max_leak)) {
      add = g.added;
      how = "grown inside its box";
    } else if (on_floor) {
      add = base_points(o, cloud, f, owned_[o.mission]);
      how = "its growth leaks out of its box (" + leak_note(g) + "), only its base added";
      if (c_.leak_growth == LeakGrowth::own_box) {
        // What leaks is the thing it touches, beyond its own extent; within
        // that extent the connected points are its own (a sparse scan's
        // difference may flag only part of a desk's whole box).
        Box own{o.bbox_min, o.bbox_max};
        own.lo.z() = f.clear_z;
        const Growth inside = grow(o.points, cloud, own, f.clear_z, owned_[o.mission]);
        std::vector<uint32_t> both;
        std::set_union(add.begin(), add.end(), inside.added.begin(), inside.added.end(), std::back_inserter(both));
        add = std::move(both);
        how = "its growth leaks out of its box (" + leak_note(g) + "), grown inside its own box and base";
      }
    } else {
      how = "its growth leaks out of its box (" + leak_note(g) + "), not grown";
    }
    if (c_.static_check && !add.empty()) {
      // Only a growth mostly held unchanged elsewhere is cut back: a short
      // move whose partner was not paired also overlaps its other pose
      // (measured on exp2-3 with drift: up to 0.74 of such growths held
      // elsewhere; a phantom sliver of static structure 0.93).
      std::vector<uint32_t> changed = not_static(add, cloud, own_floor_region(o), neighbours(o.mission), clouds_, c_);
      const double share = 1.0 - double(changed.size()) / double(add.size());
      if (share >= c_.static_share) {
        st_.points_static += add.size() - changed.size();
        how += ", " + std::to_string(add.size() - changed.size()) + " points held unchanged elsewhere left out";
        add = std::move(changed);
      }
    }
    st_.object_notes.push_back("object " + std::to_string(o.id) + ": " + how + ", " + std::to_string(add.size()) +
                               " points added");
    if (add.empty()) continue;
    ++st_.self_completed;
    add_points(o, cloud.points, add);
    for (uint32_t i : add) owned_[o.mission][point_key(cloud.points.scan[i], cloud.points.index[i])] = 0;  // membership only
    st_.points_added += add.size();
    o.update_geometry();
  }
}

void CompletionPass::absorb_nested_objects() {
  if (c_.nested_share > 0.0) st_.absorbed = absorb_nested(out_, c_.nested_share, 0.5f * float(c_.voxel));
}

// The floor each object stands on (Object::floor_z), for descriptors that
// measure heights from it. An object whose lowest point is more than
// on_floor_gap above the local floor stands on something else (a table, a
// shelf): its floor stays unknown and its lowest point is its base. An
// object that came with a floor and left unchanged (segment.complete again
// after segment.carve) keeps it: the floor is measured on points gathered
// around this pass's pairs, and remeasured it moves by microns (13 of exp3
// seed 24's 28 floors, up to 0.14 mm) for no reason.
void CompletionPass::set_floors(const FloorsCameWith& came_with) {
  auto came_with_floor = [&](const Object& o) {
    const auto kept = came_with.find({o.mission, point_key(o.points.scan[0], o.points.index[0])});
    return kept != came_with.end() && kept->second.first == o.points.size() ? kept : came_with.end();
  };
  const std::vector<std::optional<Floor>> floors =
      own_floors([&](const Object& o) { return came_with_floor(o) == came_with.end(); });
  for (size_t k = 0; k < out_.objects.size(); ++k) {
    Object& o = out_.objects[k];
    if (o.points.empty()) continue;
    if (const auto kept = came_with_floor(o); kept != came_with.end()) {
      o.floor_z = kept->second.second;
      ++st_.floors;
      continue;
    }
    if (!floors[k] || o.bbox_min.z() - floors[k]->z > kOnFloorGap) continue;
    o.floor_z = floors[k]->z;
    ++st_.floors;
  }
}

}  // namespace lista::segment::completion
