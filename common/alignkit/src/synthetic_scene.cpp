#include <lista_alignkit/synthetic_scene.hpp>

#include <cmath>
#include <limits>

namespace lista::alignkit::testing {

namespace {

void add_box(Scene& s, Eigen::Vector3d a, Eigen::Vector3d b) { s.boxes.push_back({a.cwiseMin(b), a.cwiseMax(b)}); }

// Ray-box slab test: distance to the first hit in front of the origin, or inf.
double hit(const Box& box, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (std::abs(d[k]) < 1e-12) {
      if (o[k] < box.min[k] || o[k] > box.max[k]) return std::numeric_limits<double>::infinity();
      continue;
    }
    double a = (box.min[k] - o[k]) / d[k], b = (box.max[k] - o[k]) / d[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return std::numeric_limits<double>::infinity();
  }
  return t0;
}

}  // namespace

Scene make_hall(double sx, double sy, int furniture, uint32_t seed) {
  Scene s;
  const double h = 3.0, w = 0.2;
  add_box(s, {-1, -1, -0.1}, {sx + 1, sy + 1, 0});          // floor
  add_box(s, {-1, -1, h}, {sx + 1, sy + 1, h + 0.1});       // ceiling
  add_box(s, {-w, -w, 0}, {0, sy + w, h});                  // walls
  add_box(s, {sx, -w, 0}, {sx + w, sy + w, h});
  add_box(s, {0, -w, 0}, {sx, 0, h});
  add_box(s, {0, sy, 0}, {sx, sy + w, h});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0.3, sx - 0.3), uy(0.3, sy - 0.3), size(0.3, 1.5), height(0.4, 2.5);
  int placed = 0;
  while (placed < furniture) {
    const Eigen::Vector3d c(ux(rng), uy(rng), 0);
    // Keep a 2 m wide lane free around the route (inset 4 m from the walls).
    const bool on_route_x = std::abs(c.y() - 4) < 1.8 || std::abs(c.y() - (sy - 4)) < 1.8;
    const bool on_route_y = std::abs(c.x() - 4) < 1.8 || std::abs(c.x() - (sx - 4)) < 1.8;
    const bool within_loop = c.x() > 2.2 && c.x() < sx - 2.2 && c.y() > 2.2 && c.y() < sy - 2.2;
    if ((on_route_x || on_route_y) && within_loop) continue;
    const double a = size(rng), b = size(rng);
    add_box(s, {c.x() - a / 2, c.y() - b / 2, 0}, {c.x() + a / 2, c.y() + b / 2, height(rng)});
    ++placed;
  }
  return s;
}

Scene make_field(uint32_t seed) {
  Scene s;
  add_box(s, {-100, -100, -0.1}, {100, 100, 0});
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-30, 30);
  for (int i = 0; i < 6; ++i) {
    const double x = u(rng), y = u(rng);
    add_box(s, {x, y, 0}, {x + 0.1, y + 0.1, 4.0});
  }
  return s;
}

PointSet cast_scan(const Scene& scene, const Eigen::Isometry3d& pose, uint32_t scan_index, std::mt19937& rng,
                   int rings) {
  PointSet out;
  std::normal_distribution<double> noise(0.0, 0.01);
  const Eigen::Vector3d origin = pose.translation();
  uint32_t index = 0;
  for (int r = 0; r < rings; ++r) {
    const double el = (-15.0 + 30.0 * r / (rings - 1)) * M_PI / 180.0;
    for (int a = 0; a < 360; ++a, ++index) {
      const double az = a * M_PI / 180.0;
      const Eigen::Vector3d d_sensor(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const Eigen::Vector3d d = pose.linear() * d_sensor;
      double best = 40.0;
      for (const auto& b : scene.boxes) best = std::min(best, hit(b, origin, d));
      if (best >= 40.0) continue;
      const double range = best + noise(rng);
      out.xyz.push_back((d_sensor * range).cast<float>());
      out.scan.push_back(scan_index);
      out.index.push_back(index);
    }
  }
  return out;
}

std::vector<Eigen::Isometry3d> loop_route(double sx, double sy, double inset, double step, double phase,
                                          double lateral) {
  const std::vector<Eigen::Vector2d> corners = {
      {inset, inset}, {sx - inset, inset}, {sx - inset, sy - inset}, {inset, sy - inset}};
  double perimeter = 0.0;
  for (size_t i = 0; i < 4; ++i) perimeter += (corners[(i + 1) % 4] - corners[i]).norm();
  std::vector<Eigen::Isometry3d> poses;
  for (double s = 0.0; s < perimeter; s += step) {
    double along = std::fmod(s + phase, perimeter);
    size_t i = 0;
    while (along > (corners[(i + 1) % 4] - corners[i]).norm()) {
      along -= (corners[(i + 1) % 4] - corners[i]).norm();
      i = (i + 1) % 4;
    }
    const Eigen::Vector2d dir = (corners[(i + 1) % 4] - corners[i]).normalized();
    const Eigen::Vector2d left(-dir.y(), dir.x());
    const Eigen::Vector2d p = corners[i] + dir * along + left * lateral;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(std::atan2(dir.y(), dir.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(p.x(), p.y(), 1.0);
    poses.push_back(pose);
  }
  return poses;
}

std::vector<Eigen::Isometry3d> drifted(const std::vector<Eigen::Isometry3d>& truth, double yaw_rate,
                                       double scale_error, const Eigen::Isometry3d& map_from_world) {
  std::vector<Eigen::Isometry3d> out;
  if (truth.empty()) return out;
  Eigen::Isometry3d current = map_from_world * truth[0];
  out.push_back(current);
  for (size_t i = 1; i < truth.size(); ++i) {
    Eigen::Isometry3d delta = truth[i - 1].inverse() * truth[i];
    const double length = delta.translation().norm();
    delta.translation() *= 1.0 + scale_error;
    delta.linear() = Eigen::AngleAxisd(yaw_rate * length, Eigen::Vector3d::UnitZ()).toRotationMatrix() * delta.linear();
    current = current * delta;
    out.push_back(current);
  }
  return out;
}

Mission make_mission(const std::string& name, const Scene& scene, const std::vector<Eigen::Isometry3d>& truth,
                     const std::vector<Eigen::Isometry3d>& poses, uint32_t seed, int rings) {
  Mission m;
  m.name = name;
  m.dir = "/nonexistent/" + name;
  std::mt19937 rng(seed);
  for (size_t i = 0; i < truth.size(); ++i) {
    Scan s;
    s.file = std::to_string(i) + ".pcd";
    s.timestamp = static_cast<double>(i);
    s.pose = poses[i];
    auto points = std::make_shared<PointSet>(cast_scan(scene, truth[i], static_cast<uint32_t>(i), rng, rings));
    s.points_in_file = static_cast<uint32_t>(points->size());
    s.points = std::move(points);
    m.scans.push_back(std::move(s));
  }
  m.poses_gt = truth;
  return m;
}

}  // namespace lista::alignkit::testing
