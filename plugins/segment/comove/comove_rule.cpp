#include "comove_rule.hpp"

#include <lista_geometry/object_geometry.hpp>
#include <lista_geometry/radius_grid.hpp>
#include <lista_geometry/union_find.hpp>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <tuple>

namespace lista::segment {
namespace {

constexpr size_t kSample = 200;                     // points of a piece judged (strided)
constexpr double kLeastTurn = 10.0 * M_PI / 180.0;  // with position_tolerance: smaller is no move

// A yaw and a translation (objects stand on floors), plus the floors' height
// difference.
struct Motion {
  Eigen::Matrix2d r = Eigen::Matrix2d::Identity();
  Eigen::Vector2d t = Eigen::Vector2d::Zero();
  double dz = 0.0;
  Eigen::Vector3f apply(const Eigen::Vector3f& p) const {
    const Eigen::Vector2d xy = r * p.head<2>().cast<double>() + t;
    return Eigen::Vector3d(xy.x(), xy.y(), double(p.z()) + dz).cast<float>();
  }
  Motion inverse() const {
    Motion m;
    m.r = r.transpose();
    m.t = -(m.r * t);
    m.dz = -dz;
    return m;
  }
};

// The points of one mission's candidate pieces, hashed for "is anything
// within the radius".
struct PieceCloud {
  std::vector<Eigen::Vector3f> xyz;
  geometry::RadiusGrid grid;
  PieceCloud(const ObjectSet& set, const std::vector<size_t>& objects, double radius) : grid(float(radius)) {
    for (size_t o : objects)
      for (const auto& p : set.objects[o].points.xyz) grid.add(p, uint32_t(xyz.size())), xyz.push_back(p);
  }
  bool near(const Eigen::Vector3f& q) const { return grid.any_near(xyz, q); }
};

struct Piece {
  size_t object;             // index into the input's objects
  Eigen::Vector2d centroid;  // horizontal
  std::vector<Eigen::Vector3f> sample;
};

bool slender(const Object& o, double ratio) {
  if (ratio <= 0) return true;
  const double height = o.bbox_max.z() - o.bbox_min.z();
  return height >= ratio * geometry::horizontal_extents(o.points.xyz).y();
}

std::vector<Piece> pieces_of(const ObjectSet& set, uint32_t mission, uint8_t against, const ComoveConfig& c) {
  std::vector<Piece> out;
  for (size_t i = 0; i < set.objects.size(); ++i) {
    const Object& o = set.objects[i];
    if (o.mission != mission || o.points.size() < 3 || !(o.points.changed_against_all() & against)) continue;
    if (!slender(o, c.slender_ratio)) continue;
    Piece p{i, o.centroid.head<2>().cast<double>(), {}};
    const size_t stride = std::max<size_t>(1, o.points.size() / kSample);
    for (size_t k = 0; k < o.points.size(); k += stride) p.sample.push_back(o.points.xyz[k]);
    out.push_back(std::move(p));
  }
  return out;
}

double floor_of(const Object& o) { return std::isfinite(o.floor_z) ? double(o.floor_z) : double(o.bbox_min.z()); }

// The motion carrying centroids a0 -> b0 and a1 -> b1 (directions matched,
// midpoints matched).
Motion motion_from(const Eigen::Vector2d& a0, const Eigen::Vector2d& a1, const Eigen::Vector2d& b0,
                   const Eigen::Vector2d& b1) {
  const Eigen::Vector2d da = a1 - a0, db = b1 - b0;
  const double yaw = std::atan2(db.y(), db.x()) - std::atan2(da.y(), da.x());
  Motion m;
  m.r = Eigen::Rotation2Dd(yaw).toRotationMatrix();
  m.t = 0.5 * (b0 + b1) - m.r * (0.5 * (a0 + a1));
  return m;
}

bool covered(const Piece& p, const Motion& m, const PieceCloud& other, double share) {
  size_t hits = 0;
  for (const auto& q : p.sample) hits += other.near(m.apply(q)) ? 1 : 0;
  return double(hits) >= share * double(p.sample.size());
}

struct Hypothesis {
  std::vector<size_t> first, second;  // object indices, ascending
  size_t points = 0;
};

// Coverage tests (of at most kSample points each) one mission pair may
// spend: a regular grid of posts (rack uprights) offers a hypothesis for
// every pair of pairs; the search stops there, and the stage says so.
constexpr size_t kBudget = 30000;

// Grows a side from its two seeds: every covered piece within join_gap of
// the set joins, until none does, as long as the set's horizontal bounding
// box stays within a diagonal of sqrt(2) x max_extent (no longer footprint
// could pass the final check). Empty when a seed is not covered or the
// budget ran out (`spent` counts coverage tests).
std::vector<size_t> grow(const ObjectSet& set, const std::vector<Piece>& pieces, size_t s0, size_t s1,
                         const Motion& m, const PieceCloud& other, const ComoveConfig& c, size_t& spent) {
  if (spent >= kBudget) return {};
  std::vector<std::optional<bool>> cover(pieces.size());
  auto is_covered = [&](size_t k) {
    if (!cover[k]) cover[k] = covered(pieces[k], m, other, c.cover_share), ++spent;
    return *cover[k];
  };
  if (!is_covered(s0) || !is_covered(s1)) return {};
  std::vector<size_t> in = {s0, s1};
  std::vector<bool> taken(pieces.size(), false);
  taken[s0] = taken[s1] = true;
  auto box_of = [&](size_t k) { return Eigen::AlignedBox2f(set.objects[pieces[k].object].bbox_min.head<2>(),
                                                           set.objects[pieces[k].object].bbox_max.head<2>()); };
  Eigen::AlignedBox2f box = box_of(s0).merged(box_of(s1));
  const float widest = float(std::sqrt(2.0) * c.max_extent);
  for (bool grew = true; grew;) {
    grew = false;
    for (size_t k = 0; k < pieces.size(); ++k) {
      if (taken[k]) continue;
      if (spent >= kBudget) return {};
      const Eigen::AlignedBox2f with = box.merged(box_of(k));
      if (with.diagonal().norm() > widest) continue;
      const Object& o = set.objects[pieces[k].object];
      const bool near = std::any_of(in.begin(), in.end(), [&](size_t j) {
        return geometry::box_gap(o, set.objects[pieces[j].object]) <= c.join_gap;
      });
      if (near && is_covered(k)) in.push_back(k), taken[k] = grew = true, box = with;
    }
  }
  std::vector<size_t> objects;
  for (size_t k : in) objects.push_back(pieces[k].object);
  std::sort(objects.begin(), objects.end());
  return objects;
}

bool fits_extent(const ObjectSet& set, const std::vector<size_t>& members, double max_extent) {
  std::vector<Eigen::Vector3f> pts;
  for (size_t i : members) pts.insert(pts.end(), set.objects[i].points.xyz.begin(), set.objects[i].points.xyz.end());
  return geometry::horizontal_extents(pts).x() <= max_extent;
}

// The joins of one consecutive pair, as groups of object indices; `cut`
// set when the search ran out of budget.
std::vector<Hypothesis> joins_between(const ObjectSet& set, uint32_t m, const ComoveConfig& c, bool& cut) {
  const std::vector<Piece> a = pieces_of(set, m, changed_against_next, c);
  const std::vector<Piece> b = pieces_of(set, m + 1, changed_against_previous, c);
  if (a.size() < 2 || b.size() < 2) return {};
  auto objects_of = [](const std::vector<Piece>& s) {
    std::vector<size_t> out;
    for (const auto& p : s) out.push_back(p.object);
    return out;
  };
  const PieceCloud grid_a(set, objects_of(a), c.cover_radius), grid_b(set, objects_of(b), c.cover_radius);
  auto close_pairs = [&](const std::vector<Piece>& s) {
    std::vector<std::pair<size_t, size_t>> out;
    for (size_t i = 0; i < s.size(); ++i)
      for (size_t j = i + 1; j < s.size(); ++j)
        if (geometry::box_gap(set.objects[s[i].object], set.objects[s[j].object]) <= c.join_gap) out.emplace_back(i, j);
    return out;
  };
  const auto pairs_a = close_pairs(a), pairs_b = close_pairs(b);
  // A piece the other mission's pieces cover where it stands did not move
  // (a symmetric layout turned about its middle lands on itself too).
  std::vector<bool> in_place(a.size());
  for (size_t i = 0; i < a.size(); ++i) in_place[i] = covered(a[i], Motion{}, grid_b, c.cover_share);

  std::vector<Hypothesis> found;
  std::set<std::pair<std::vector<size_t>, std::vector<size_t>>> seen;
  size_t spent = 0;
  for (const auto& [i, j] : pairs_a) {
    if (spent >= kBudget) {
      cut = true;
      break;
    }
    if (in_place[i] && in_place[j]) continue;
    const double da = (a[j].centroid - a[i].centroid).norm();
    for (const auto& [k0, l0] : pairs_b) {
      if (std::abs((b[l0].centroid - b[k0].centroid).norm() - da) > c.position_tolerance) continue;
      for (const auto& [k, l] : {std::pair{k0, l0}, std::pair{l0, k0}}) {
        Motion mo = motion_from(a[i].centroid, a[j].centroid, b[k].centroid, b[l].centroid);
        const double turn = std::abs(Eigen::Rotation2Dd(mo.r).smallestAngle());
        if ((mo.r * a[i].centroid + mo.t - a[i].centroid).norm() < c.position_tolerance && turn < kLeastTurn) continue;
        mo.dz = 0.5 * (floor_of(set.objects[b[k].object]) + floor_of(set.objects[b[l].object]) -
                       floor_of(set.objects[a[i].object]) - floor_of(set.objects[a[j].object]));
        Hypothesis h;
        h.first = grow(set, a, i, j, mo, grid_b, c, spent);
        if (h.first.empty()) continue;
        h.second = grow(set, b, k, l, mo.inverse(), grid_a, c, spent);
        if (h.second.empty()) continue;
        if (!seen.insert({h.first, h.second}).second) continue;
        if (!fits_extent(set, h.first, c.max_extent) || !fits_extent(set, h.second, c.max_extent)) continue;
        for (size_t o : h.first) h.points += set.objects[o].points.size();
        for (size_t o : h.second) h.points += set.objects[o].points.size();
        found.push_back(std::move(h));
      }
    }
  }
  // Most points first; ties by the members' ids, so the order of discovery
  // does not matter.
  std::sort(found.begin(), found.end(), [](const Hypothesis& x, const Hypothesis& y) {
    if (x.points != y.points) return x.points > y.points;
    return std::tie(x.first, x.second) < std::tie(y.first, y.second);
  });
  std::vector<Hypothesis> chosen;
  std::vector<bool> used(set.objects.size(), false);
  for (auto& h : found) {
    auto free = [&](const std::vector<size_t>& v) { return std::none_of(v.begin(), v.end(), [&](size_t o) { return used[o]; }); };
    if (!free(h.first) || !free(h.second)) continue;
    for (size_t o : h.first) used[o] = true;
    for (size_t o : h.second) used[o] = true;
    chosen.push_back(std::move(h));
  }
  return chosen;
}

}  // namespace

ObjectSet join_comoving(const ObjectSet& given, const ComoveConfig& config, ComoveStats* stats) {
  ObjectSet in = given;  // bounds and centroids recomputed: an upstream stage may have left them stale
  for (auto& o : in.objects) o.update_geometry();
  const size_t n = in.objects.size();
  geometry::UnionFind groups(n);  // the lowest index roots a group, so the joined object takes its place
  ComoveStats st;
  for (uint32_t m = 0; m + 1 < in.missions.size(); ++m) {
    bool cut = false;
    const std::vector<Hypothesis> joins = joins_between(in, m, config, cut);
    if (cut) st.searches_cut.push_back(m);
    for (const Hypothesis& h : joins)
      for (const auto* side : {&h.first, &h.second})
        for (size_t o : *side) groups.unite((*side)[0], o);
  }

  ObjectSet out;
  out.missions = in.missions;
  out.dynamics = in.dynamics;
  std::vector<long> slot(n, -1);
  std::vector<bool> grown(n, false);  // roots that took another piece
  for (size_t i = 0; i < n; ++i) {
    const size_t r = groups.find(i);
    if (r == i) {
      slot[i] = long(out.objects.size());
      out.objects.push_back(in.objects[i]);
      continue;
    }
    Object& into = out.objects[size_t(slot[r])];
    if (!grown[r]) grown[r] = true, ++st.joins;
    into.points.append(in.objects[i].points);
    if (std::isfinite(in.objects[i].floor_z) && !(into.floor_z <= in.objects[i].floor_z)) into.floor_z = in.objects[i].floor_z;
    ++st.joined;
  }
  if (st.joined > 0) {
    for (size_t i = 0; i < n; ++i)
      if (grown[i]) out.objects[size_t(slot[i])].update_geometry();
    out.renumber();
  }
  st.joined += st.joins;  // the roots count as pieces too
  if (stats) *stats = st;
  return out;
}

}  // namespace lista::segment
