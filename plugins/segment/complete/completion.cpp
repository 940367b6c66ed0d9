#include "completion.hpp"

#include <lista/error.hpp>
#include <lista_geometry/object_geometry.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <deque>
#include <iterator>
#include <limits>
#include <map>
#include <thread>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

namespace lista::seg {
namespace {

struct Box {
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  bool contains(const Eigen::Vector3f& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
  void extend(const Box& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  Box grown(float xy, float z_down, float z_up) const {
    Box b = *this;
    b.lo -= Eigen::Vector3f(xy, xy, z_down);
    b.hi += Eigen::Vector3f(xy, xy, z_up);
    return b;
  }
};

using geometry::box_gap;

// Rounds of joining: a joined fragment's growth may reach one more.
constexpr int kJoinRounds = 3;
// Joined shapes must agree within this share of the pair check's allowance:
// joining claims more than pairing, and the pair check's allowance is wide
// enough for a desk in one mission to pass for a barrel and a cart touching
// in the other (measured on tiny seed 3).
constexpr double kJoinStrictness = 0.5;

uint64_t point_key(uint32_t scan, uint32_t index) { return (uint64_t(scan) << 32) | index; }

// Appends the mission cloud's points `add` to an object. They carry no
// change channel (they are the mission's points, not change points); they
// are part of the same changed object, so they take its ChangedAgainst bits.
void add_points(Object& o, const PointSet& cloud, const std::vector<uint32_t>& add) {
  const bool known = o.points.has_changed_against();
  const uint8_t bits = o.points.changed_against_all();
  std::vector<uint8_t> against = std::move(o.points.changed_against);
  o.points.changed_against.clear();
  for (uint32_t i : add) o.points.push_back_from(cloud, i);
  if (known) {
    against.resize(o.points.size(), bits);
    o.points.changed_against = std::move(against);
  }
}

using geometry::voxel_key;

// One mission's points near its objects and pairs, with a voxel index.
struct LocalCloud {
  PointSet points;                                  // common frame
  std::vector<std::pair<uint64_t, uint32_t>> grid;  // (voxel key, point), sorted
  float inv_voxel = 10.f;

  Eigen::Vector3i voxel_of(const Eigen::Vector3f& p) const {
    return (p * inv_voxel).array().floor().cast<int>();
  }
  void index() {
    grid.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) grid[i] = {voxel_key(voxel_of(points.xyz[i])), uint32_t(i)};
    std::sort(grid.begin(), grid.end());
  }
  // Points in voxel v: a range of `grid`.
  std::pair<size_t, size_t> in_voxel(const Eigen::Vector3i& v) const {
    const uint64_t k = voxel_key(v);
    auto lo = std::lower_bound(grid.begin(), grid.end(), std::make_pair(k, uint32_t(0)));
    auto hi = lo;
    while (hi != grid.end() && hi->first == k) ++hi;
    return {size_t(lo - grid.begin()), size_t(hi - grid.begin())};
  }
};

// Gathers the points of `mission` (common frame) that fall inside any of
// `regions`, in scan then file order whatever the thread count.
LocalCloud gather(const Mission& mission, const std::vector<Box>& regions, float voxel, int threads) {
  LocalCloud cloud;
  cloud.inv_voxel = 1.f / voxel;
  if (regions.empty()) return cloud;
  Box all;
  for (const auto& r : regions) all.extend(r);
  const size_t n = mission.scans.size();
  std::vector<PointSet> per_scan(n);
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t s; (s = next++) < n;) {
      const Scan& scan = mission.scans[s];
      if (!scan.points) continue;
      const Eigen::Affine3f T = mission.sensor_to_common(s).cast<float>();
      const PointSet& src = *scan.points;
      PointSet& out = per_scan[s];
      for (size_t i = 0; i < src.size(); ++i) {
        const Eigen::Vector3f p = T * src.xyz[i];
        if (!all.contains(p)) continue;
        bool in = false;
        for (const auto& r : regions)
          if ((in = r.contains(p))) break;
        if (!in) continue;
        out.push_back_from(src, i);
        out.xyz.back() = p;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  for (auto& s : per_scan) cloud.points.append(s);
  cloud.index();
  return cloud;
}

// The points of `cloud` inside any of `regions`, in the same order: what
// gather(regions) would have returned, without reading the mission again.
LocalCloud restrict_to(const LocalCloud& cloud, const std::vector<Box>& regions) {
  LocalCloud out;
  out.inv_voxel = cloud.inv_voxel;
  for (size_t i = 0; i < cloud.points.size(); ++i)
    for (const auto& r : regions)
      if (r.contains(cloud.points.xyz[i])) {
        out.points.push_back_from(cloud.points, i);
        break;
      }
  out.index();
  return out;
}

// The local floor under `region`: the `percentile` of the lowest z per 0.2 m
// cell gives a first guess f0 (robust to objects covering part of the cells);
// the floor is the median of the points within 6 cm above f0 and its noise
// their MAD. Points below floor + max(min_clearance, 4 sigma) count as floor.
struct Floor {
  float z = 0.f;          // floor height
  float clear_z = 0.f;    // lowest z an object point may have
};

bool local_floor(const PointSet& pts, const Box& region, double percentile, double min_clearance, Floor& floor) {
  std::vector<std::tuple<int, int, float>> cells;
  for (const auto& p : pts.xyz)
    if (region.contains(p)) cells.emplace_back(int(std::floor(p.x() * 5.f)), int(std::floor(p.y() * 5.f)), p.z());
  if (cells.empty()) return false;
  std::sort(cells.begin(), cells.end());
  std::vector<float> lowest;
  for (size_t i = 0; i < cells.size(); ++i)
    if (i == 0 || std::get<0>(cells[i]) != std::get<0>(cells[i - 1]) ||
        std::get<1>(cells[i]) != std::get<1>(cells[i - 1]))
      lowest.push_back(std::get<2>(cells[i]));
  std::sort(lowest.begin(), lowest.end());
  const float f0 = lowest[std::min(lowest.size() - 1, size_t(percentile * double(lowest.size())))];
  std::vector<float> band;
  for (const auto& c : cells)
    if (std::get<2>(c) >= f0 && std::get<2>(c) <= f0 + 0.06f) band.push_back(std::get<2>(c));
  auto median = [](std::vector<float>& v) {
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  floor.z = median(band);
  for (auto& z : band) z = std::abs(z - floor.z);
  const float sigma = 1.4826f * median(band);
  floor.clear_z = floor.z + std::max(float(min_clearance), 4.f * sigma);
  return true;
}

// Breadth-first growth of `seed` through occupied voxels of `cloud` inside
// `region`, over points above `min_z` that nobody owns. Returns the new points.
struct Growth {
  std::vector<uint32_t> added;  // new points, ascending
  size_t voxels = 0;            // voxels it added points from
  size_t leaks = 0;             // voxels it would have entered outside the region
  std::vector<uint32_t> touched;  // objects (indices) owning points the walk reached, ascending
  // A growth that wants out of its region is part of something bigger (a
  // wall, the desk the object touches): not one object.
  bool contained(double max_leak) const { return double(leaks) <= max_leak * double(std::max<size_t>(voxels, 1)); }
};

// Point key -> index of the object that holds the point, per mission.
using Owners = std::unordered_map<uint64_t, uint32_t>;

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

// Height above the floor and the footprint-rectangle sides
// (larger first) of an object grown by `extra` points of `cloud`.
Eigen::Vector3f shape_of(const PointSet& own, const std::vector<uint32_t>& extra, const PointSet& cloud,
                         float floor, float min_z) {
  std::vector<Eigen::Vector3f> pts;
  for (const auto& p : own.xyz)
    if (p.z() >= min_z) pts.push_back(p);
  for (uint32_t i : extra) pts.push_back(cloud.xyz[i]);
  if (pts.size() < 3) return Eigen::Vector3f::Zero();
  float top = std::numeric_limits<float>::lowest();
  for (const auto& p : pts) top = std::max(top, p.z());
  const Eigen::Vector2f e = geometry::horizontal_extents(pts);
  return {top - floor, e[0], e[1]};
}

std::string format_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", v);
  return text;
}

// "height x side x side m" of shape_of's result.
std::string shape_note(const Eigen::Vector3f& s) {
  return format_number(s[0]) + " x " + format_number(s[1]) + " x " + format_number(s[2]) + " m";
}

// Leaked voxels per voxel grown into.
std::string leak_note(const Growth& g) {
  return format_number(double(g.leaks) / double(std::max<size_t>(g.voxels, 1)));
}

bool same_shape(const Eigen::Vector3f& a, const Eigen::Vector3f& b, const CompletionConfig& c, double strictness = 1.0) {
  for (int k = 0; k < 3; ++k) {
    const double allowed = strictness * std::max(c.shape_slack, c.shape_tolerance * std::max(a[k], b[k]));
    if (std::abs(a[k] - b[k]) > allowed) return false;
  }
  return true;
}

// The base of an object standing on the floor: points of `cloud` below its
// lowest detected part, down to the floor clearance, in the 5 cm columns its
// lowest 15 cm occupy (grown by one column). The volumetric difference cannot
// confirm change that close to the floor (the floor voxel is occupied in both
// missions), so this is where a detected object most often lacks points.
std::vector<uint32_t> base_points(const Object& o, const LocalCloud& cloud, const Floor& floor,
                                  const Owners& owned) {
  std::unordered_set<uint64_t> columns;
  auto column = [](float x, float y) {
    return voxel_key(Eigen::Vector3i(int(std::floor(x * 20.f)), int(std::floor(y * 20.f)), 0));
  };
  for (const auto& p : o.points.xyz)
    if (p.z() < o.bbox_min.z() + 0.15f) {
      const int cx = int(std::floor(p.x() * 20.f)), cy = int(std::floor(p.y() * 20.f));
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy) columns.insert(voxel_key(Eigen::Vector3i(cx + dx, cy + dy, 0)));
    }
  std::vector<uint32_t> added;
  const float top = o.bbox_min.z() + 0.05f;
  for (size_t i = 0; i < cloud.points.size(); ++i) {
    const auto& p = cloud.points.xyz[i];
    if (p.z() < floor.clear_z || p.z() > top || !columns.count(column(p.x(), p.y()))) continue;
    if (owned.count(point_key(cloud.points.scan[i], cloud.points.index[i]))) continue;
    added.push_back(uint32_t(i));
  }
  return added;
}

constexpr float kSurfaceNoise = 0.02f;  // m: a scanned flat surface's points lie within this of its height

// On how many of its four sides a thin object's own mission continues its
// surface: a side counts when at least half of its 0.1 m columns, in a
// strip `ring` wide along the object's box, hold a point of `own` within
// `tol` of the object's median height. A patch of a larger horizontal
// surface (a shelf's top, a table's) has three or four; a thing standing
// free at that height (a cart's deck) none; the sliver of a table top moved
// a little, one (the rest of the top).
int surface_sides(const Object& o, const LocalCloud& own, float ring, float tol) {
  std::vector<float> z;
  z.reserve(o.points.size());
  for (const auto& p : o.points.xyz) z.push_back(p.z());
  std::nth_element(z.begin(), z.begin() + std::ptrdiff_t(z.size() / 2), z.end());
  const float zc = z[z.size() / 2];
  constexpr float kColumn = 0.1f;
  auto column = [&](float v) { return int(std::floor(v / kColumn)); };
  const int ix0 = column(o.bbox_min.x()), ix1 = column(o.bbox_max.x());
  const int iy0 = column(o.bbox_min.y()), iy1 = column(o.bbox_max.y());
  const int w = std::max(1, int(std::ceil(ring / kColumn)));
  // Side of column (x, y): 0 -x, 1 +x, 2 -y, 3 +y; -1 inside the box, in a
  // corner or beyond the strips.
  auto side = [&](int x, int y) {
    const bool in_x = x >= ix0 && x <= ix1, in_y = y >= iy0 && y <= iy1;
    if (in_y && x < ix0 && x >= ix0 - w) return 0;
    if (in_y && x > ix1 && x <= ix1 + w) return 1;
    if (in_x && y < iy0 && y >= iy0 - w) return 2;
    if (in_x && y > iy1 && y <= iy1 + w) return 3;
    return -1;
  };
  const size_t cells[4] = {size_t(w) * size_t(iy1 - iy0 + 1), size_t(w) * size_t(iy1 - iy0 + 1),
                           size_t(w) * size_t(ix1 - ix0 + 1), size_t(w) * size_t(ix1 - ix0 + 1)};
  std::unordered_set<uint64_t> held[4];
  for (const auto& p : own.points.xyz) {
    if (std::abs(p.z() - zc) > tol) continue;
    const int x = column(p.x()), y = column(p.y()), k = side(x, y);
    if (k >= 0) held[k].insert(voxel_key(Eigen::Vector3i(x, y, 0)));
  }
  int sides = 0;
  for (int k = 0; k < 4; ++k) sides += 2 * held[k].size() >= cells[k];
  return sides;
}

// Whether every one of the `neighbours`' clouds holds a point in a voxel,
// above its own local floor under `floor_region`. Not valid when a neighbour
// has no points there: it saw nothing of the place and cannot say it is
// static.
struct HeldElsewhere {
  std::vector<std::pair<const LocalCloud*, float>> others;  // cloud, lowest z that counts
  bool valid = false;

  HeldElsewhere(const Box& floor_region, const std::vector<size_t>& neighbours, const std::vector<LocalCloud>& clouds,
                const CompletionConfig& c) {
    if (neighbours.empty()) return;
    for (size_t n : neighbours) {
      Floor f;
      if (!local_floor(clouds[n].points, floor_region, c.floor_percentile, c.floor_clearance, f)) return;
      others.emplace_back(&clouds[n], f.clear_z);
    }
    valid = true;
  }
  bool everywhere(const Eigen::Vector3i& v) const {
    for (const auto& [other, min_z] : others) {
      const auto [b, e] = other->in_voxel(v);
      bool held = false;
      for (size_t k = b; k < e && !held; ++k) held = other->points.xyz[other->grid[k].second].z() >= min_z;
      if (!held) return false;
    }
    return true;
  }
};

// The points of `add` (in `cloud`) whose voxel is not occupied, above the
// local floor, in every one of the `neighbours`' clouds: the rest is there in
// the other missions too, so it did not change.
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

// Rule 6: an object whose points lie mostly (`share`) inside the box of a
// larger object of the same mission (grown by half a voxel) is a fragment of
// it: growth stops at points another object owns, so two clusters of one
// object stay two, interleaved in the same box. Smallest first, so a chain of
// fragments ends in the largest. Returns how many objects were absorbed.
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
  if (absorbed == 0) return 0;
  std::vector<Object> kept;
  for (size_t i = 0; i < set.objects.size(); ++i)
    if (!gone[i]) kept.push_back(std::move(set.objects[i]));
  set.objects = std::move(kept);
  set.renumber();
  return absorbed;
}

// Rule 4b: joins the objects of one mission that its cloud connects over
// changed points. `candidates`: (gap, i, j) same-mission pairs of free
// objects, nearest first. Growth from i inside the union of the two boxes
// grown by box_margin (down to the floor) must reach j over points it
// adds, and at most 1 - static_share of those may lie where every
// neighbouring mission holds points too: the material between them changed
// with them (a table's top between the legs the difference found). Objects
// whose voxels touch are left apart: segment.carve and segment.overlap cut
// them so on purpose. Each component joins its largest member; returns how
// many objects joined another (ids renumbered when any did).
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
    if (!local_floor(cloud.points, floor_region, c.floor_percentile, c.floor_clearance, f)) continue;
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
  std::vector<Object> kept;
  for (size_t k = 0; k < n; ++k)
    if (!gone[k]) {
      set.objects[k].update_geometry();
      kept.push_back(std::move(set.objects[k]));
    }
  set.objects = std::move(kept);
  set.renumber();
  return joined;
}

}  // namespace

ObjectSet complete_objects(const ObjectSet& input, const MissionSet& missions, const CompletionConfig& c,
                           CompletionStats* stats) {
  if (c.voxel <= 0) throw Error("segment.complete: voxel must be > 0");
  ObjectSet out = input;
  // What each object came with (by mission and first point): an object this
  // pass leaves as it came keeps its floor (rule 7).
  std::map<std::pair<uint32_t, uint64_t>, std::pair<size_t, float>> came_with;
  for (const auto& o : out.objects)
    if (!o.points.empty() && std::isfinite(o.floor_z))
      came_with[{o.mission, point_key(o.points.scan[0], o.points.index[0])}] = {o.points.size(), o.floor_z};
  for (auto& o : out.objects) o.update_geometry();
  std::vector<const Mission*> mission_of(out.missions.size(), nullptr);
  for (size_t m = 0; m < out.missions.size(); ++m) {
    mission_of[m] = missions.find(out.missions[m]);
    if (!mission_of[m])
      throw Error("segment.complete: objects name mission '" + out.missions[m] +
                  "', which the missions input does not hold; connect the missions the objects came from");
  }
  for (const auto& o : out.objects)
    if (o.mission >= out.missions.size())
      throw Error("segment.complete: object " + std::to_string(o.id) + " names mission index " +
                  std::to_string(o.mission) + " of " + std::to_string(out.missions.size()));

  const float margin = float(c.box_margin);
  auto own_floor_region = [&](const Object& o) {
    return Box{o.bbox_min, o.bbox_max}.grown(margin + 0.75f, 1.5f, margin);
  };
  auto pair_region = [&](const Object& a, const Object& b) {
    Box r;
    for (const Object* o : {&a, &b}) r.extend(Box{o->bbox_min, o->bbox_max});
    return r;
  };
  // Candidate pairs across consecutive missions, nearest first. Boxes that
  // overlap are all 0 m apart, and gaps under one growth voxel are all
  // "touching" to the growth; among those the nearer centroids (horizontal)
  // come first, so a short move's two slivers go before a neighbour whose
  // box merely reaches into theirs.
  auto candidate_pairs = [&] {
    std::vector<std::tuple<float, float, float, size_t, size_t>> candidates;
    for (size_t i = 0; i < out.objects.size(); ++i)
      for (size_t j = 0; j < out.objects.size(); ++j) {
        const Object &a = out.objects[i], &b = out.objects[j];
        if (b.mission != a.mission + 1 || a.points.empty() || b.points.empty()) continue;
        const float gap = box_gap(a, b);
        if (gap > c.pair_gap) continue;
        if (c.centroid_order)
          candidates.emplace_back(std::floor(gap / float(c.voxel)), (a.centroid - b.centroid).head<2>().norm(), gap, i, j);
        else
          candidates.emplace_back(gap, 0.f, 0.f, i, j);
      }
    std::sort(candidates.begin(), candidates.end());
    return candidates;
  };
  // Rule 4b's candidates: free objects of one mission whose boxes are at
  // most pair_gap apart, nearest first (`paired`: objects a completed pair
  // holds, aligned with out.objects; empty = none).
  auto connected_candidates = [&](const std::vector<char>& paired) {
    std::vector<std::tuple<float, size_t, size_t>> candidates;
    for (size_t i = 0; i < out.objects.size(); ++i)
      for (size_t j = i + 1; j < out.objects.size(); ++j) {
        const Object &a = out.objects[i], &b = out.objects[j];
        if (a.mission != b.mission || a.points.empty() || b.points.empty()) continue;
        if (!paired.empty() && (paired[i] || paired[j])) continue;
        const float gap = box_gap(a, b);
        if (gap <= c.pair_gap) candidates.emplace_back(gap, i, j);
      }
    std::sort(candidates.begin(), candidates.end());
    return candidates;
  };
  CompletionStats st;

  // Each mission's points around its objects and around every candidate
  // pair: rule 0 needs each object's floor before the pairs are known.
  const size_t nm = out.missions.size();
  auto neighbours = [&](size_t m) {
    std::vector<size_t> n;
    if (m > 0) n.push_back(m - 1);
    if (m + 1 < nm) n.push_back(m + 1);
    return n;
  };
  // Every object's own region: its floor is measured (rules 0 and 7)
  // whether or not it self-completes.
  auto add_own_regions = [&](std::vector<std::vector<Box>>& regions, bool with_neighbours) {
    for (const auto& o : out.objects) {
      if (o.points.empty()) continue;
      regions[o.mission].push_back(own_floor_region(o));
      if (with_neighbours)
        for (size_t n : neighbours(o.mission)) regions[n].push_back(own_floor_region(o));
    }
  };
  // Rule 4b grows in the union of two boxes of one mission and asks the
  // neighbouring missions what they hold there.
  auto add_connected_regions = [&](std::vector<std::vector<Box>>& regions) {
    if (!c.join_connected) return;
    for (const auto& [gap, i, j] : connected_candidates({})) {
      const Object &a = out.objects[i], &b = out.objects[j];
      const Box r = pair_region(a, b).grown(margin + 0.75f, 1.5f, margin);
      regions[a.mission].push_back(r);
      for (size_t n : neighbours(a.mission)) regions[n].push_back(r);
    }
  };
  std::vector<std::vector<Box>> first_regions(nm);
  for (const auto& [order, apart, gap, i, j] : candidate_pairs()) {
    const Box r = pair_region(out.objects[i], out.objects[j]).grown(margin + 0.75f, 1.5f, margin);
    first_regions[out.objects[i].mission].push_back(r);
    first_regions[out.objects[j].mission].push_back(r);
  }
  add_own_regions(first_regions, (c.self_complete && c.static_check) || c.thin_height > 0.0);
  add_connected_regions(first_regions);
  std::vector<LocalCloud> clouds(nm);
  for (size_t m = 0; m < nm; ++m) clouds[m] = gather(*mission_of[m], first_regions[m], float(c.voxel), c.threads);

  // 0. The floor itself is no object: a cluster lying (floor_share of its
  // points) within the floor clearance of its local floor, at most
  // kFloorObjectHeight, is ground the difference flagged (grazing beams,
  // uneven ground between scans), never a thing that moved. Dropped before
  // pairing so it pairs with nothing.
  if (c.floor_share > 0.0) {
    std::vector<Object> kept;
    for (auto& o : out.objects) {
      Floor f;
      if (!o.points.empty() && local_floor(clouds[o.mission].points, own_floor_region(o), c.floor_percentile,
                                           c.floor_clearance, f)) {
        const float top = std::min(f.clear_z, f.z + kFloorObjectHeight);
        size_t low = 0;
        for (const auto& p : o.points.xyz) low += p.z() < top;
        if (double(low) >= c.floor_share * double(o.points.size())) {
          ++st.floor_only;
          continue;
        }
      }
      kept.push_back(std::move(o));
    }
    out.objects = std::move(kept);
  }
  // 0b. A thin cluster (under thin_height tall) whose voxels every
  // neighbouring mission also holds is a horizontal surface that did not
  // change (a table top grazed by beams); a thin object that did change (a
  // cart's deck seen from above) is not held where it was. Nor is a patch
  // of a surface the other mission's beams grazed without hitting (a
  // sparse scanner, a rack's low shelf): its own mission continues the
  // surface on thin_surface_sides of its four sides.
  if (c.thin_height > 0.0) {
    std::vector<Object> kept;
    for (auto& o : out.objects) {
      if (!o.points.empty() && o.bbox_max.z() - o.bbox_min.z() < float(c.thin_height)) {
        const HeldElsewhere held(own_floor_region(o), neighbours(o.mission), clouds, c);
        if (held.valid) {
          size_t n = 0;
          for (const auto& p : o.points.xyz) n += held.everywhere(clouds[o.mission].voxel_of(p));
          if (double(n) >= c.static_share * double(o.points.size())) {
            ++st.thin_static;
            continue;
          }
        }
        if (c.thin_surface_sides > 0 &&
            surface_sides(o, clouds[o.mission], margin, kSurfaceNoise) >= c.thin_surface_sides) {
          ++st.thin_surface;
          continue;
        }
      }
      kept.push_back(std::move(o));
    }
    out.objects = std::move(kept);
  }
  if (st.floor_only || st.thin_static || st.thin_surface) out.renumber();

  // 1. Pairs, nearest first, each object in at most one completed pair.
  // With pair_retry, a pair whose growth is refused frees both objects for
  // their next-nearest candidates (two slivers of one short move whose boxes
  // touch a third object's as closely: the first candidate may be the wrong one).
  struct Pair {
    size_t a, b;
    Box own, region, floor_region;  // own: the union of the two boxes, no margin
  };
  std::vector<Pair> pairs;
  {
    std::vector<char> used(out.objects.size(), 0);
    for (const auto& [order, apart, gap, i, j] : candidate_pairs()) {
      if (!c.pair_retry) {
        if (used[i] || used[j]) continue;
        used[i] = used[j] = 1;
      }
      const Box r = pair_region(out.objects[i], out.objects[j]);
      // Down to the floor: the region's lower bound is set once the floor is known.
      pairs.push_back({i, j, r, r.grown(margin, 0.f, margin), r.grown(margin + 0.75f, 1.5f, margin)});
    }
  }

  // 2. Each mission's points around the pairs to try and the kept objects
  // (a dropped object's points need not stay). The leak check looks one
  // voxel past a region, well inside its gathered floor region.
  std::vector<std::vector<Box>> regions(nm);
  for (const auto& p : pairs)
    for (size_t k : {p.a, p.b}) regions[out.objects[k].mission].push_back(p.floor_region);
  add_own_regions(regions, c.self_complete && c.static_check);
  add_connected_regions(regions);
  for (size_t m = 0; m < nm; ++m) clouds[m] = restrict_to(clouds[m], regions[m]);
  std::vector<Owners> owned(nm);
  for (size_t k = 0; k < out.objects.size(); ++k) {
    const Object& o = out.objects[k];
    for (size_t i = 0; i < o.points.size(); ++i) owned[o.mission][point_key(o.points.scan[i], o.points.index[i])] = uint32_t(k);
  }

  // 3-4. Grow both objects of each pair; keep the growth if the shapes agree.
  // With join_fragments, a growth that reaches points of other free objects
  // of its own mission (a short move with a turn leaves slivers at both ends
  // of a desk) is tried again with them in the seed and their boxes in the
  // region; if those shapes agree, they are joined into the pair's object.
  std::vector<char> completed(out.objects.size(), 0), gone(out.objects.size(), 0);
  struct Attempt {
    Growth ga, gb;
    Eigen::Vector3f sa, sb;
    bool contained = false, same = false;
    std::string kept_to;
    std::vector<uint32_t> touched_a, touched_b;  // free objects the growths reached
  };
  for (const auto& p : pairs) {
    if (completed[p.a] || completed[p.b] || gone[p.a] || gone[p.b]) continue;
    ++st.pairs;
    Object &a = out.objects[p.a], &b = out.objects[p.b];
    const LocalCloud &ca = clouds[a.mission], &cb = clouds[b.mission];
    Floor fa, fb;
    const std::string which = "objects " + std::to_string(a.id) + " + " + std::to_string(b.id) + ": ";
    if (!local_floor(ca.points, p.floor_region, c.floor_percentile, c.floor_clearance, fa) ||
        !local_floor(cb.points, p.floor_region, c.floor_percentile, c.floor_clearance, fb)) {
      ++st.rejected;
      st.pair_notes.push_back(which + "not completed, no floor found around them");
      continue;
    }
    const float floor_a = fa.z, floor_b = fb.z, min_a = fa.clear_z, min_b = fb.clear_z;
    std::vector<uint32_t> self{uint32_t(p.a), uint32_t(p.b)};
    auto free_touched = [&](const std::vector<uint32_t>& touched) {
      std::vector<uint32_t> f;
      for (uint32_t k : touched)
        if (std::find(self.begin(), self.end(), k) == self.end() && !completed[k] && !gone[k] &&
            !out.objects[k].points.empty())
          f.push_back(k);
      return f;
    };
    // `own`: the union of the seeds' boxes, no margin.
    auto attempt = [&](const PointSet& seed_a, const PointSet& seed_b, const Box& own, double strictness) {
      Attempt t;
      auto grow_both = [&](const Box& region) {
        Box ra = region, rb = region;
        ra.lo.z() = std::min(ra.lo.z(), min_a);
        rb.lo.z() = std::min(rb.lo.z(), min_b);
        t.ga = grow(seed_a, ca, ra, min_a, owned[a.mission]);
        t.gb = grow(seed_b, cb, rb, min_b, owned[b.mission]);
        t.sa = shape_of(seed_a, t.ga.added, ca.points, floor_a, min_a);
        t.sb = shape_of(seed_b, t.gb.added, cb.points, floor_b, min_b);
      };
      grow_both(own.grown(margin, 0.f, margin));
      t.touched_a = free_touched(t.ga.touched);
      t.touched_b = free_touched(t.gb.touched);
      t.contained = t.ga.contained(c.max_leak) && t.gb.contained(c.max_leak);
      if (!t.contained && c.leak_own_box) {
        // As in step 5: what leaks is the thing they touch; the pair's own
        // box (the two clusters' union, no margin) holds the object. The
        // shapes must still agree.
        t.kept_to = " inside the pair's own box (a growth leaked: " + leak_note(t.ga) + " / " + leak_note(t.gb) + ")";
        grow_both(own);
        t.contained = true;
      }
      t.same = t.contained && same_shape(t.sa, t.sb, c, strictness);
      return t;
    };
    Attempt t = attempt(a.points, b.points, p.own, 1.0);
    std::vector<uint32_t> join_a, join_b;
    if (c.join_fragments && (!t.touched_a.empty() || !t.touched_b.empty())) {
      // Both sides' fragments, else one side's only (the other side's growth
      // may reach a different object touching it, as a desk touches a
      // cabinet added beside it).
      const size_t self_size = self.size();
      auto try_join = [&](bool side_a, bool side_b, std::vector<uint32_t>& ja, std::vector<uint32_t>& jb) {
        self.resize(self_size);
        PointSet seed_a = a.points, seed_b = b.points;
        Box own = p.own;
        Attempt joined = t;
        auto pending = [&] { return (side_a && !joined.touched_a.empty()) || (side_b && !joined.touched_b.empty()); };
        for (int round = 0; round < kJoinRounds && pending(); ++round) {
          for (auto [use, touched, seed, into] : {std::tuple{side_a, &joined.touched_a, &seed_a, &ja},
                                                  std::tuple{side_b, &joined.touched_b, &seed_b, &jb}})
            if (use)
              for (uint32_t k : *touched) {
                const Object& f = out.objects[k];
                seed->append(f.points);
                own.extend(Box{f.bbox_min, f.bbox_max});
                into->push_back(k);
                self.push_back(k);
              }
          joined = attempt(seed_a, seed_b, own, kJoinStrictness);
        }
        return joined;
      };
      const bool both = !t.touched_a.empty() && !t.touched_b.empty();
      std::vector<std::pair<bool, bool>> tries;
      if (both) tries = {{true, true}, {true, false}, {false, true}};
      else tries = {{!t.touched_a.empty(), !t.touched_b.empty()}};
      for (auto [side_a, side_b] : tries) {
        std::vector<uint32_t> ja, jb;
        Attempt joined = try_join(side_a, side_b, ja, jb);
        if (joined.same) {
          t = std::move(joined);
          join_a = std::move(ja);
          join_b = std::move(jb);
          break;
        }
        std::string tried;
        for (uint32_t k : ja) tried += (tried.empty() ? "" : ", ") + std::to_string(out.objects[k].id);
        for (uint32_t k : jb) tried += (tried.empty() ? "" : ", ") + std::to_string(out.objects[k].id);
        st.pair_notes.push_back(which + "not joined with " + tried + ", " +
                                (!joined.contained ? "a growth leaks out of the region"
                                                   : "joined shapes differ" + joined.kept_to + " (" +
                                                         shape_note(joined.sa) + " / " + shape_note(joined.sb) + ")"));
      }
      self.resize(self_size);
      for (uint32_t k : join_a) self.push_back(k);
      for (uint32_t k : join_b) self.push_back(k);
    }
    if (!t.same) {
      ++st.rejected;
      st.pair_notes.push_back(which + "not completed, " +
                              (!t.contained ? "a growth leaks out of the pair's region (" + leak_note(t.ga) + " / " +
                                                  leak_note(t.gb) + ", max_leak " + format_number(c.max_leak) + ")"
                                            : "grown shapes differ" + t.kept_to + " (" + shape_note(t.sa) + " / " +
                                                  shape_note(t.sb) + ")"));
      continue;
    }
    ++st.completed;
    completed[p.a] = completed[p.b] = 1;
    std::string joined_note;
    for (auto [join, into] : {std::pair{&join_a, &a}, std::pair{&join_b, &b}})
      for (uint32_t k : *join) {
        Object& f = out.objects[k];
        joined_note += (joined_note.empty() ? " (joined: " : ", ") + std::to_string(f.id) + " to " + std::to_string(into->id);
        into->points.append(f.points);
        const uint32_t to = uint32_t(into == &a ? p.a : p.b);
        for (size_t i = 0; i < f.points.size(); ++i) owned[f.mission][point_key(f.points.scan[i], f.points.index[i])] = to;
        f.points = PointSet();
        gone[k] = 1;
        ++st.joined;
      }
    if (!joined_note.empty()) joined_note += ")";
    st.pair_notes.push_back(which + "completed" + joined_note + t.kept_to + ", " + std::to_string(t.ga.added.size()) +
                            " + " + std::to_string(t.gb.added.size()) + " points added (" + shape_note(t.sa) + " / " +
                            shape_note(t.sb) + ")");
    for (auto [o, add, cloud, index] :
         {std::tuple{&a, &t.ga.added, &ca, uint32_t(p.a)}, std::tuple{&b, &t.gb.added, &cb, uint32_t(p.b)}}) {
      add_points(*o, cloud->points, *add);
      for (uint32_t i : *add) owned[o->mission][point_key(cloud->points.scan[i], cloud->points.index[i])] = index;
      st.points_added += add->size();
      o->update_geometry();
    }
  }
  std::vector<char> paired;  // aligned with out.objects from here
  for (size_t k = 0; k < out.objects.size(); ++k)
    if (!gone[k]) paired.push_back(completed[k]);
  if (st.joined) {
    std::vector<Object> kept;
    for (size_t k = 0; k < out.objects.size(); ++k)
      if (!gone[k]) kept.push_back(std::move(out.objects[k]));
    out.objects = std::move(kept);
    out.renumber();
    // owned's object indices are stale from here; later rules only test membership.
  }

  // 4b. Free objects of one mission connected over changed points are one
  // object the difference cut apart (a table's legs without its top).
  if (c.join_connected) {
    std::vector<std::vector<size_t>> neighbour_lists(nm);
    for (size_t m = 0; m < nm; ++m) neighbour_lists[m] = neighbours(m);
    st.connected = join_connected(out, connected_candidates(paired), clouds, neighbour_lists, c, st.object_notes);
  }

  // 5. Every object: its own missing points inside its box grown by
  // box_margin (mostly its base next to the floor, and surfaces the
  // difference left out next to others), or only its base when the growth
  // wants out of the box (the object touches a wall or other furniture).
  if (c.self_complete)
    for (auto& o : out.objects) {
      if (o.points.empty()) continue;
      const LocalCloud& cloud = clouds[o.mission];
      Floor f;
      if (!local_floor(cloud.points, own_floor_region(o), c.floor_percentile, c.floor_clearance, f)) continue;
      Box r = Box{o.bbox_min, o.bbox_max}.grown(margin, margin, margin);
      const bool on_floor = o.bbox_min.z() - f.z <= kOnFloorGap;
      if (on_floor) r.lo.z() = f.clear_z;
      const Growth g = grow(o.points, cloud, r, f.clear_z, owned[o.mission]);
      std::vector<uint32_t> add;
      std::string how;
      if (g.contained(c.max_leak)) {
        add = g.added;
        how = "grown inside its box";
      } else if (on_floor) {
        add = base_points(o, cloud, f, owned[o.mission]);
        how = "its growth leaks out of its box (" + leak_note(g) + "), only its base added";
        if (c.leak_own_box) {
          // What leaks is the thing it touches, beyond its own extent; within
          // that extent the connected points are its own (a sparse scan's
          // difference may flag only part of a desk's whole box).
          Box own{o.bbox_min, o.bbox_max};
          own.lo.z() = f.clear_z;
          const Growth inside = grow(o.points, cloud, own, f.clear_z, owned[o.mission]);
          std::vector<uint32_t> both;
          std::set_union(add.begin(), add.end(), inside.added.begin(), inside.added.end(), std::back_inserter(both));
          add = std::move(both);
          how = "its growth leaks out of its box (" + leak_note(g) + "), grown inside its own box and base";
        }
      } else {
        how = "its growth leaks out of its box (" + leak_note(g) + "), not grown";
      }
      if (c.static_check && !add.empty()) {
        // Only a growth mostly held unchanged elsewhere is cut back: a short
        // move whose partner was not paired also overlaps its other pose
        // (measured on exp2-3 with drift: up to 0.74 of such growths held
        // elsewhere; a phantom sliver of static structure 0.93).
        std::vector<uint32_t> changed = not_static(add, cloud, own_floor_region(o), neighbours(o.mission), clouds, c);
        const double share = 1.0 - double(changed.size()) / double(add.size());
        if (share >= c.static_share) {
          st.points_static += add.size() - changed.size();
          how += ", " + std::to_string(add.size() - changed.size()) + " points held unchanged elsewhere left out";
          add = std::move(changed);
        }
      }
      st.object_notes.push_back("object " + std::to_string(o.id) + ": " + how + ", " + std::to_string(add.size()) +
                                " points added");
      if (add.empty()) continue;
      ++st.self_completed;
      add_points(o, cloud.points, add);
      for (uint32_t i : add) owned[o.mission][point_key(cloud.points.scan[i], cloud.points.index[i])] = 0;  // membership only
      st.points_added += add.size();
      o.update_geometry();
    }

  if (c.nested_share > 0.0) st.absorbed = absorb_nested(out, c.nested_share, 0.5f * float(c.voxel));

  // 7. The floor each object stands on (Object::floor_z), for descriptors
  // that measure heights from it. An object whose lowest point is more than
  // on_floor_gap above the local floor stands on something else (a table, a
  // shelf): its floor stays unknown and its lowest point is its base.
  // An object that came with a floor and left unchanged (segment.complete
  // again after segment.carve) keeps it: the floor is measured on points
  // gathered around this pass's pairs, and remeasured it moves by microns
  // (13 of exp3 seed 24's 28 floors, up to 0.14 mm) for no reason.
  for (auto& o : out.objects) {
    if (o.points.empty()) continue;
    const auto kept = came_with.find({o.mission, point_key(o.points.scan[0], o.points.index[0])});
    if (kept != came_with.end() && kept->second.first == o.points.size()) {
      o.floor_z = kept->second.second;
      ++st.floors;
      continue;
    }
    Floor f;
    if (!local_floor(clouds[o.mission].points, own_floor_region(o), c.floor_percentile, c.floor_clearance, f)) continue;
    if (o.bbox_min.z() - f.z > kOnFloorGap) continue;
    o.floor_z = f.z;
    ++st.floors;
  }
  if (stats) *stats = st;
  return out;
}

}  // namespace lista::seg
