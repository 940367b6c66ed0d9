#include <lista_raycast/synthetic_scene.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace lista::raycast {

namespace {

struct Box {
  Eigen::Vector3d lo, hi;
  uint32_t label;
};

// Entry distance of a ray into a solid box (slab test); +inf if missed.
double enter(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t0 = 0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (o[k] < b.lo[k] || o[k] > b.hi[k]) return t1;
      continue;
    }
    double a = (b.lo[k] - o[k]) / d[k], c = (b.hi[k] - o[k]) / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
  }
  return t0 <= t1 && t0 > 1e-9 ? t0 : std::numeric_limits<double>::infinity();
}

// Exit distance of a ray from inside the room box.
double leave(const Box& room, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] > 1e-12) t = std::min(t, (room.hi[k] - o[k]) / d[k]);
    if (d[k] < -1e-12) t = std::min(t, (room.lo[k] - o[k]) / d[k]);
  }
  return t;
}

PointSet scan_at(const Eigen::Isometry3d& world_sensor, const std::vector<Box>& solids, const Box& room,
                 const SyntheticSceneConfig& c, std::mt19937_64& rng, uint32_t scan_id) {
  std::normal_distribution<double> noise(0.0, c.range_noise);
  PointSet s;
  const Eigen::Vector3d o = world_sensor.translation();
  uint32_t index = 0;
  for (int r = 0; r < c.rings; ++r) {
    const double el = (-45.0 + 90.0 * r / std::max(1, c.rings - 1)) * M_PI / 180.0;
    for (int a = 0; a < c.columns; ++a, ++index) {
      const double az = 2.0 * M_PI * a / c.columns;
      const Eigen::Vector3d d_s(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const Eigen::Vector3d d = world_sensor.linear() * d_s;
      double t = leave(room, o, d);
      uint32_t label = 0;
      for (const Box& b : solids) {
        const double tb = enter(b, o, d);
        if (tb < t) {
          t = tb;
          label = b.label;
        }
      }
      const double range = t + noise(rng);
      s.xyz.push_back((d_s * range).cast<float>());
      s.intensity.push_back(static_cast<float>(10.0 + label));
      s.label.push_back(label);
      s.scan.push_back(scan_id);
      s.index.push_back(index);
    }
  }
  return s;
}

}  // namespace

MissionSet make_synthetic_scene(const SyntheticSceneConfig& c) {
  const double k = c.scale;
  const Box room{{-6 * k, -4 * k, 0}, {6 * k, 4 * k, 3}, 0};
  const Box partition{{1.9 * k, -4 * k, 0}, {2.1 * k, 4 * k, 3}, 0};
  const Box removed{{-2 * k, 0.5 * k, 0}, {-2 * k + 0.6, 0.5 * k + 0.6, 0.6}, 1};
  const Box hidden{{4 * k, -1 * k, 0}, {4 * k + 0.6, -1 * k + 0.6, 0.8}, 2};
  const Box added{{-3.5 * k, -2 * k, 0}, {-3.5 * k + 0.5, -2 * k + 0.5, 0.5}, 3};
  const Box stay{{0, 2 * k, 0}, {0.5, 2 * k + 0.5, 1.0}, 4};

  struct Plan {
    std::string name;
    std::vector<Box> solids;
    std::vector<Eigen::Vector3d> positions;  // x, y, yaw
    Eigen::Isometry3d to_common;
  };
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  offset.translate(Eigen::Vector3d(0.7, -0.3, 0.1));
  offset.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  const std::vector<Plan> plans = {
      {"A", {partition, removed, hidden, stay},
       {{-4 * k, 0, 0.1}, {-1 * k, -2 * k, 1.0}, {0.5 * k, 0, 2.0}, {4 * k, 1 * k, 0.5}, {5 * k, -2.5 * k, 3.0}},
       Eigen::Isometry3d::Identity()},
      {"B", {partition, added, stay},
       {{-4 * k, 0.3 * k, 0.7}, {-1 * k, -1.8 * k, 2.2}, {0.5 * k, 0.2 * k, 4.0}},
       offset},
  };

  std::mt19937_64 rng(c.seed);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  MissionSet set;
  set.dataset = "synthetic";
  for (const Plan& plan : plans) {
    Mission m;
    m.name = m.dir = plan.name;
    m.to_common = plan.to_common;
    for (const Eigen::Vector3d& p : plan.positions) {
      for (int rep = 0; rep < c.scans_per_position; ++rep) {
        const double j = rep == 0 ? 0.0 : 1.0;  // first scan exactly at the planned spot
        Eigen::Isometry3d world = Eigen::Isometry3d::Identity();
        world.translate(Eigen::Vector3d(p.x() + j * jitter(rng), p.y() + j * jitter(rng), 1.2));
        world.rotate(Eigen::AngleAxisd(p.z() + j * jitter(rng), Eigen::Vector3d::UnitZ()));
        Scan s;
        s.file = plan.name + "/" + std::to_string(m.scans.size());
        s.timestamp = static_cast<double>(m.scans.size());
        s.pose = plan.to_common.inverse() * world;  // in the mission's own map frame
        auto pts = std::make_shared<PointSet>(
            scan_at(world, plan.solids, room, c, rng, static_cast<uint32_t>(m.scans.size())));
        s.points_in_file = static_cast<uint32_t>(pts->size());
        s.points = std::move(pts);
        m.poses_gt.push_back(world);
        m.scans.push_back(std::move(s));
      }
    }
    set.missions.push_back(std::move(m));
  }
  return set;
}

}  // namespace lista::raycast
