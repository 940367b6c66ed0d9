#include "scenario.hpp"

#include "rng.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <cmath>
#include <set>

namespace lista::sim {
namespace {

using V2 = Eigen::Vector2d;
using Iso = Eigen::Isometry3d;

constexpr uint32_t kFirstPersonId = 10000;  // people get ids well above objects
constexpr double kGap = 0.05;               // free space kept between placed things, m

Iso floor_pose(const V2& xy, double yaw) {
  Iso t = Iso::Identity();
  t.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(xy.x(), xy.y(), 0.0);
  return t;
}

double yaw_of(const Iso& t) { return std::atan2(t.linear()(1, 0), t.linear()(0, 0)); }

template <typename T>
void shuffle(std::vector<T>& v, Rng& rng) {
  for (size_t i = v.size(); i > 1; --i) std::swap(v[i - 1], v[size_t(rng.integer(0, int(i) - 1))]);
}

// Placement bookkeeping for one mission being built.
class World {
 public:
  World(const Scenario& sc, std::map<uint32_t, Iso>& present)
      : sc_(sc), present_(present), fixed_(sc.layout.obstacles) {
    for (const auto& c : sc.layout.corridor()) fixed_.push_back(c);
  }

  Footprint footprint(uint32_t id, const Iso& pose) const {
    return footprint_of(sc_.shapes[size_t(sc_.object_shape.at(id))], pose);
  }

  // True if a shape at `pose` fits: inside the area, clear of structure, the
  // route and every present object other than `ignore`.
  bool fits(int shape, const Iso& pose, uint32_t ignore = 0) const {
    const Footprint f = footprint_of(sc_.shapes[size_t(shape)], pose);
    const auto& l = sc_.layout;
    const double r = f.half.norm();
    if (f.centre.x() - r < l.area_min.x() || f.centre.y() - r < l.area_min.y() ||
        f.centre.x() + r > l.area_max.x() || f.centre.y() + r > l.area_max.y())
      return false;
    if (overlaps_any(f, fixed_, kGap)) return false;
    for (const auto& [id, p] : present_)
      if (id != ignore && overlaps(f, footprint(id, p), kGap)) return false;
    return true;
  }

  Iso random_pose(Rng& rng) const {
    const auto& l = sc_.layout;
    const V2 xy(rng.uniform(l.area_min.x(), l.area_max.x()), rng.uniform(l.area_min.y(), l.area_max.y()));
    // Furniture tends to be aligned with the walls; some of it is not.
    const double yaw = rng.chance(0.6) ? rng.integer(0, 3) * M_PI / 2 + rng.normal() * 0.05
                                       : rng.uniform(-M_PI, M_PI);
    return floor_pose(xy, yaw);
  }

 private:
  const Scenario& sc_;
  std::map<uint32_t, Iso>& present_;
  std::vector<Footprint> fixed_;
};

// Where this mission's changes are, for the spacing rules of exp2 / exp3.
struct ChangeRegions {
  ChangeSpacing spacing;
  std::vector<Footprint> regions;
  bool accepts(const Footprint& f) const {
    switch (spacing) {
      case ChangeSpacing::separate: return !overlaps_any(f, regions, 1.0);
      case ChangeSpacing::overlap: return regions.empty() || overlaps_any(f, regions, 1.0);
      default: return true;
    }
  }
};

int new_shape(Scenario& sc, const ChangeParams& p, Rng& rng) {
  if (!p.extra_shapes.empty() && rng.chance(0.3)) {
    sc.shapes.push_back(p.extra_shapes[size_t(rng.integer(0, int(p.extra_shapes.size()) - 1))]);
  } else {
    const auto& cls = p.classes[size_t(rng.integer(0, int(p.classes.size()) - 1))];
    sc.shapes.push_back(make_shape(cls, rng.next() & 0xFFFFFFFFull));
  }
  return int(sc.shapes.size()) - 1;
}

// Places a new object of `shape`; returns 0 if no free spot was found.
uint32_t place_new(Scenario& sc, World& world, std::map<uint32_t, Iso>& present, int shape, uint32_t id,
                   ChangeRegions* regions, Rng& rng) {
  for (int attempt = 0; attempt < 400; ++attempt) {
    const Iso pose = world.random_pose(rng);
    if (!world.fits(shape, pose)) continue;
    const Footprint f = footprint_of(sc.shapes[size_t(shape)], pose);
    if (regions && !regions->accepts(f) && attempt < 300) continue;
    sc.object_shape[id] = shape;
    present[id] = pose;
    if (regions) regions->regions.push_back(f);
    return id;
  }
  return 0;
}

void populate(Scenario& sc, MissionPlan& first, const ChangeParams& p, uint32_t& next_id, Rng& rng) {
  World world(sc, first.objects);
  std::vector<int> used;
  int dups_left = std::max(p.duplicates, 2 * p.swaps);
  for (int i = 0; i < p.objects; ++i) {
    const int remaining = p.objects - i;
    int shape;
    if (!used.empty() && dups_left > 0 && rng.uniform() * remaining < dups_left + 0.5) {
      shape = used[size_t(rng.integer(0, int(used.size()) - 1))];
      --dups_left;
    } else {
      shape = new_shape(sc, p, rng);
    }
    if (place_new(sc, world, first.objects, shape, next_id, nullptr, rng)) {
      ++next_id;
      used.push_back(shape);
    }
  }
}

void apply_changes(Scenario& sc, MissionPlan& m, const ChangeParams& p, uint32_t& next_id, Rng& rng) {
  World world(sc, m.objects);
  ChangeRegions regions{p.spacing, {}};
  std::set<uint32_t> changed;
  auto eligible = [&] {
    std::vector<uint32_t> ids;
    for (const auto& [id, pose] : m.objects)
      if (!changed.count(id)) ids.push_back(id);
    shuffle(ids, rng);
    return ids;
  };

  int removed = 0;
  for (uint32_t id : eligible()) {
    if (removed == p.removals) break;
    const Footprint f = world.footprint(id, m.objects[id]);
    if (!regions.accepts(f)) continue;
    regions.regions.push_back(f);
    m.objects.erase(id);
    changed.insert(id);
    sc.change_kind[id].push_back("removed");
    ++removed;
  }

  int swapped = 0;
  for (uint32_t a : eligible()) {
    if (swapped == p.swaps) break;
    if (changed.count(a)) continue;
    for (const auto& [b, pose_b] : m.objects) {
      if (b == a || changed.count(b) || sc.object_shape[b] != sc.object_shape[a]) continue;
      const Footprint fa = world.footprint(a, m.objects[a]), fb = world.footprint(b, pose_b);
      if (!regions.accepts(fa) || !regions.accepts(fb)) continue;
      std::swap(m.objects[a], m.objects[b]);
      regions.regions.push_back(fa);
      regions.regions.push_back(fb);
      changed.insert(a);
      changed.insert(b);
      sc.change_kind[a].push_back("swapped");
      sc.change_kind[b].push_back("swapped");
      ++swapped;
      break;
    }
  }

  int moved = 0;
  for (uint32_t id : eligible()) {
    if (moved == p.moves) break;
    const int shape = sc.object_shape[id];
    const Shape& s = sc.shapes[size_t(shape)];
    const Iso old_pose = m.objects[id];
    const Footprint old_f = world.footprint(id, old_pose);
    if (p.spacing == ChangeSpacing::separate && !regions.accepts(old_f)) continue;
    const bool short_move = moved < p.short_moves;
    bool done = false;
    for (int attempt = 0; attempt < 300 && !done; ++attempt) {
      Iso pose;
      if (short_move) {  // shorter than the object itself: old and new overlap
        const double dir = rng.uniform(-M_PI, M_PI);
        const double dist = std::max(0.12, rng.uniform(0.25, 0.7) * s.size());
        pose = floor_pose(old_pose.translation().head<2>() + dist * V2(std::cos(dir), std::sin(dir)),
                          yaw_of(old_pose) + rng.uniform(-0.5, 0.5));
      } else {
        pose = world.random_pose(rng);
        if ((pose.translation() - old_pose.translation()).norm() < std::max(1.5, 1.5 * s.size())) continue;
      }
      if (!world.fits(shape, pose, id)) continue;
      const Footprint f = footprint_of(s, pose);
      if (!regions.accepts(f) && attempt < 200) continue;
      m.objects[id] = pose;
      regions.regions.push_back(old_f);
      regions.regions.push_back(f);
      done = true;
    }
    if (!done) continue;
    changed.insert(id);
    sc.change_kind[id].push_back(short_move ? "moved (short)" : "moved");
    ++moved;
  }

  int added = 0;
  for (int attempt = 0; added < p.additions && attempt < 4 * std::max(1, p.additions); ++attempt) {
    std::vector<int> existing;
    for (const auto& [id, shape] : sc.object_shape)
      if (id < kFirstPersonId) existing.push_back(shape);
    const int shape = (!existing.empty() && rng.chance(0.3)) ? existing[size_t(rng.integer(0, int(existing.size()) - 1))]
                                                             : new_shape(sc, p, rng);
    if (place_new(sc, world, m.objects, shape, next_id, &regions, rng)) {
      sc.change_kind[next_id].push_back("added");
      ++next_id;
      ++added;
    }
  }
}

void add_people(Scenario& sc, MissionPlan& m, const ChangeParams& p, uint32_t& next_person, Rng& rng) {
  const auto& l = sc.layout;
  for (int k = 0; k < p.people; ++k) {
    Person person;
    person.id = next_person++;
    sc.shapes.push_back(make_person(rng.next() & 0xFFFFFFFFull));
    person.shape = int(sc.shapes.size()) - 1;
    sc.object_shape[person.id] = person.shape;
    // People walk along the route (where there is room), crossing the robot's path.
    const double s = rng.uniform(0.0, l.route_length());
    const V2 a = l.route_point(s);
    const V2 b = l.route_point(s + rng.uniform(3.0, 8.0));
    person.from = a;
    person.to = b;
    person.phase = rng.uniform();
    m.people.push_back(person);
  }
}

// The operator beside a stop-and-go scanner (ChangeParams::station_operator).
void add_operator(Scenario& sc, MissionPlan& m, uint32_t& next_person, Rng& rng) {
  Person person;
  person.id = next_person++;
  sc.shapes.push_back(make_person(rng.next() & 0xFFFFFFFFull));
  person.shape = int(sc.shapes.size()) - 1;
  sc.object_shape[person.id] = person.shape;
  person.phase = rng.uniform();
  person.beside_sensor = true;
  m.people.push_back(person);
}

void plan_route(const Scenario& sc, MissionPlan& m, int index, const RouteParams& p, Rng& rng) {
  const Layout& l = sc.layout;
  const double length = l.route_length();
  const double spacing = length / p.scans;
  const double s0 = index == 0 ? 0.0 : rng.uniform(0.0, length);
  const double amp = index == 0 ? 0.02 : p.deviation;
  const double ph1 = rng.uniform(0, 2 * M_PI), ph2 = rng.uniform(0, 2 * M_PI), ph3 = rng.uniform(0, 2 * M_PI);
  const double wl1 = rng.uniform(8, 20), wl2 = rng.uniform(3, 6);
  for (int i = 0; i < p.scans; ++i) {
    const double s = s0 + i * spacing + (index == 0 ? 0.0 : rng.uniform(-0.2, 0.2) * spacing);
    V2 tangent;
    const V2 c = l.route_point(s, &tangent);
    const V2 normal(-tangent.y(), tangent.x());
    // Smooth lateral deviation, bounded by amp (0.6 + 0.4 = 1).
    const double lateral = amp * (0.6 * std::sin(2 * M_PI * s / wl1 + ph1) + 0.4 * std::sin(2 * M_PI * s / wl2 + ph2));
    const V2 xy = c + lateral * normal;
    const double yaw = std::atan2(tangent.y(), tangent.x()) + 0.05 * std::sin(s / 1.7 + ph3);
    const double roll = 0.015 * std::sin(s * 2.1 + ph1), pitch = 0.015 * std::sin(s * 1.3 + ph2);
    Iso t = Iso::Identity();
    t.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    t.translation() = Eigen::Vector3d(xy.x(), xy.y(), l.sensor_height + 0.01 * std::sin(s * 3.0));
    if (p.spin_deg_per_s != 0.0)
      t.linear() = t.linear() * Eigen::AngleAxisd(p.spin_deg_per_s * M_PI / 180.0 * 0.1 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    m.poses_true.push_back(t);
  }

  // Map frame: gravity-aligned first pose (as a SLAM system starts its map).
  const Iso& first = m.poses_true.front();
  m.map_to_world = floor_pose(first.translation().head<2>(), yaw_of(first));
  m.map_to_world.translation().z() = first.translation().z();
  // Drawn only when asked: level datasets keep their random sequence.
  if (p.map_tilt_deg > 0.0) {
    const double direction = rng.uniform(-M_PI, M_PI);
    const Eigen::Vector3d axis(std::cos(direction), std::sin(direction), 0.0);
    m.map_to_world.linear() = m.map_to_world.linear() *
                              Eigen::AngleAxisd(-p.map_tilt_deg * M_PI / 180.0, axis).toRotationMatrix();
  }

  // Odometry drift: a biased random walk in translation and heading, about the
  // start point, growing with distance travelled.
  const double angle = rng.uniform(-M_PI, M_PI);
  const Eigen::Vector3d bias = p.drift_per_m * Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.2 * rng.normal());
  const double yaw_bias = p.yaw_drift_deg_per_m * M_PI / 180.0 * rng.normal();
  Eigen::Vector3d drift_t = Eigen::Vector3d::Zero();
  double drift_yaw = 0.0;
  const Eigen::Vector3d p0 = first.translation();
  const Iso world_to_map = m.map_to_world.inverse();
  for (size_t i = 0; i < m.poses_true.size(); ++i) {
    if (i > 0) {
      const double step = (m.poses_true[i].translation() - m.poses_true[i - 1].translation()).norm();
      drift_t += step * (bias + 0.3 * p.drift_per_m * Eigen::Vector3d(rng.normal(), rng.normal(), 0.2 * rng.normal()));
      drift_yaw += step * (yaw_bias + 0.3 * p.yaw_drift_deg_per_m * M_PI / 180.0 * rng.normal());
    }
    Iso d = Iso::Identity();
    d.linear() = Eigen::AngleAxisd(drift_yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    d.translation() = p0 + drift_t - d.linear() * p0;
    m.poses_estimated.push_back(world_to_map * d * m.poses_true[i]);
  }
}

}  // namespace

Footprint footprint_of(const Shape& shape, const Iso& pose) {
  Footprint f;
  f.centre = pose.translation().head<2>();
  f.half = shape.half_extent.cast<double>();
  f.yaw = yaw_of(pose);
  return f;
}

Iso MissionPlan::person_pose(const Person& p, size_t scan) const {
  if (p.beside_sensor) {
    // 1.5-2.5 m behind the sensor (where the route came from: free floor),
    // up to 0.6 m aside, a different place each scan.
    const Iso& station = poses_true[std::min(scan, poses_true.size() - 1)];
    const V2 at = station.translation().head<2>();
    const Eigen::Vector3d x = station.linear().col(0);
    const V2 heading = V2(x.x(), x.y()).norm() > 1e-6 ? V2(x.x(), x.y()).normalized() : V2(1.0, 0.0);
    const V2 side(-heading.y(), heading.x());
    const double k = double(scan) + 7.0 * p.phase;
    const V2 xy = at - (2.0 + 0.5 * std::sin(2.4 * k)) * heading + 0.6 * std::sin(1.7 * k + 1.0) * side;
    return floor_pose(xy, std::atan2(at.y() - xy.y(), at.x() - xy.x()));
  }
  // Back and forth once per mission: a triangle wave over the scan index.
  const double u = std::fmod(p.phase + 2.0 * double(scan) / std::max<size_t>(1, poses_true.size()), 2.0);
  const double w = u < 1.0 ? u : 2.0 - u;
  const V2 dir = (p.to - p.from).normalized();
  const double yaw = std::atan2(dir.y(), dir.x()) + (u < 1.0 ? 0.0 : M_PI);
  return floor_pose(p.from + w * (p.to - p.from), yaw);
}

Scenario plan_scenario(Layout layout, const ChangeParams& changes, const RouteParams& route, uint64_t seed) {
  if (route.missions < 1) throw Error("lista-sim: --missions must be >= 1");
  if (route.missions > 26) throw Error("lista-sim: at most 26 missions (named A..Z)");
  if (route.scans < 1) throw Error("lista-sim: scans per mission must be >= 1");
  if (changes.classes.empty()) throw Error("lista-sim: no object classes to draw from");
  Scenario sc;
  sc.layout = std::move(layout);
  Rng objects_rng(seed, hash_string("objects"));
  Rng route_rng(seed, hash_string("route"));
  Rng people_rng(seed, hash_string("people"));
  Rng operator_rng(seed, hash_string("operator"));  // its own stream: the rest is the same with or without
  uint32_t next_id = 1, next_person = kFirstPersonId;
  for (int k = 0; k < route.missions; ++k) {
    MissionPlan m;
    m.name = std::string(1, char('A' + k));
    if (k == 0) {
      populate(sc, m, changes, next_id, objects_rng);
    } else {
      m.objects = sc.missions.back().objects;
      apply_changes(sc, m, changes, next_id, objects_rng);
    }
    add_people(sc, m, changes, next_person, people_rng);
    if (changes.station_operator) add_operator(sc, m, next_person, operator_rng);
    plan_route(sc, m, k, route, route_rng);
    sc.missions.push_back(std::move(m));
  }
  return sc;
}

}  // namespace lista::sim
