#include "scanner.hpp"

#include "rng.hpp"

#include <algorithm>
#include <cmath>

namespace lista::sim {

namespace {

// Where a ray from the sensor (sensor frame) enters the body box, and the
// face's normal; t < 0 when it misses.
Hit body_hit(const Eigen::Vector3f& dir_s) {
  float t0 = 0.0f, t1 = 1e9f;
  int axis = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(dir_s[k]) < 1e-9f) {
      if (0.0f < body_box_min[k] || 0.0f > body_box_max[k]) return {};
      continue;
    }
    float a = body_box_min[k] / dir_s[k], b = body_box_max[k] / dir_s[k];
    if (a > b) std::swap(a, b);
    if (a > t0) {
      t0 = a;
      axis = k;
    }
    t1 = std::min(t1, b);
    if (t0 > t1) return {};
  }
  if (axis < 0) return {};  // the sensor inside the box: not a body it can see
  Hit h;
  h.t = t0;
  h.label = 0;
  h.reflectivity = 0.25f;  // dark painted metal
  h.normal = Eigen::Vector3f::Zero();
  h.normal[axis] = dir_s[axis] > 0 ? -1.0f : 1.0f;
  return h;
}

// The pose a `fraction` of the way from a to b: translation linear, rotation by slerp.
Eigen::Isometry3d between(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double fraction) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(a.linear()).slerp(fraction, Eigen::Quaterniond(b.linear())).toRotationMatrix();
  T.translation() = (1.0 - fraction) * a.translation() + fraction * b.translation();
  return T;
}

// Sensor-frame unit directions of one sweep, in ray order (the order in time).
std::vector<Eigen::Vector3f> ray_directions(const SensorModel& sensor, uint64_t key) {
  std::vector<Eigen::Vector3f> dirs(sensor.rays());
  if (sensor.non_repetitive()) {
    // The R2 sequence (Roberts 2018), started at a point drawn from the
    // sweep's key: evenly spread within a sweep, never the same twice.
    constexpr double kPlastic = 1.32471795724474602596;
    constexpr double a1 = 1.0 / kPlastic, a2 = 1.0 / (kPlastic * kPlastic);
    const double u0 = hash_uniform(hash_combine(key, 0x11)), v0 = hash_uniform(hash_combine(key, 0x12));
    const double z_lo = std::sin(sensor.elevation_min), z_hi = std::sin(sensor.elevation_max);
    for (size_t r = 0; r < dirs.size(); ++r) {
      const double u = std::fmod(u0 + a1 * double(r), 1.0), v = std::fmod(v0 + a2 * double(r), 1.0);
      const double az = (u - 0.5) * sensor.azimuth_fov;
      const double z = z_lo + (z_hi - z_lo) * v;  // uniform in sin(elevation): even per solid angle
      const double c = std::sqrt(std::max(0.0, 1.0 - z * z));
      dirs[r] = Eigen::Vector3d(c * std::cos(az), c * std::sin(az), z).cast<float>();
    }
    return dirs;
  }
  const size_t beams = sensor.elevations.size();
  std::vector<float> cos_e(beams), sin_e(beams);
  for (size_t b = 0; b < beams; ++b) {
    cos_e[b] = float(std::cos(sensor.elevations[b]));
    sin_e[b] = float(std::sin(sensor.elevations[b]));
  }
  for (int c = 0; c < sensor.columns; ++c) {
    const double az = 2.0 * M_PI * c / sensor.columns;
    const float ca = float(std::cos(az)), sa = float(std::sin(az));
    for (size_t b = 0; b < beams; ++b) dirs[size_t(c) * beams + b] = Eigen::Vector3f(cos_e[b] * ca, cos_e[b] * sa, sin_e[b]);
  }
  return dirs;
}

}  // namespace

PointSet sweep(const RayScene& scene, const RayScene* dynamic_scene, const SensorModel& sensor,
               const Eigen::Isometry3d& T_world_sensor, const SweepOptions& options) {
  const std::vector<Eigen::Vector3f> directions = ray_directions(sensor, options.key);
  const size_t rays = directions.size();
  // One slot per ray, compacted afterwards in ray order: the output does not
  // depend on how the threads split the work.
  std::vector<Eigen::Vector3f> xyz(rays);
  std::vector<float> intensity(rays);
  std::vector<uint32_t> label(rays);
  std::vector<uint8_t> valid(rays, 0);
  std::vector<float> time(rays, 0.0f);

  const auto cast = [&](const Eigen::Matrix3f& R, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir_s) {
    const Eigen::Vector3f dir = R * dir_s;
    Hit hit = scene.intersect(origin, dir, float(sensor.min_range), float(sensor.max_range));
    if (dynamic_scene) {
      const float tmax = hit.t > 0 ? hit.t : float(sensor.max_range);
      const Hit h2 = dynamic_scene->intersect(origin, dir, float(sensor.min_range), tmax);
      if (h2.t > 0) hit = h2;
    }
    if (options.body) {
      Hit b = body_hit(dir_s);
      if (b.t >= float(sensor.min_range) && (hit.t < 0 || b.t < hit.t)) {
        b.normal = R * b.normal;
        hit = b;
      }
    }
    return hit;
  };

#pragma omp parallel for schedule(dynamic, 1024) num_threads(std::max(1, options.threads))
  for (size_t r = 0; r < rays; ++r) {
    const double fraction = options.sweep_end ? double(r) / double(rays) : 0.0;
    const Eigen::Isometry3d at = options.sweep_end ? between(T_world_sensor, *options.sweep_end, fraction) : T_world_sensor;
    const Eigen::Matrix3f R = at.linear().cast<float>();
    const Eigen::Vector3f origin = at.translation().cast<float>();
    const Eigen::Vector3f& dir_s = directions[r];
    const Eigen::Vector3f dir = R * dir_s;
    const Hit hit = cast(R, origin, dir_s);
    if (hit.t < 0) continue;
    const uint64_t h = hash_combine(options.key, r);
    const float cos_inc = std::abs(hit.normal.dot(dir));
    // Returns get lost at random and more often at grazing incidence.
    double p_drop = sensor.dropout;
    if (cos_inc < 0.15f) p_drop += 0.5 * (0.15 - cos_inc) / 0.15;
    if (options.dark_dropouts) {
      const double signal = hit.reflectivity / 0.1 * std::max(0.05f, cos_inc) *
                            std::pow(sensor.range_dark / std::max(0.1f, hit.t), 2.0);
      if (signal < 1.0) p_drop += 1.0 - signal;
    }
    if (hash_uniform(h) < p_drop) continue;
    double true_range = hit.t;
    if (options.mixed_pixels && sensor.divergence > 0) {
      // The footprint's rim, at a direction drawn per ray: another surface
      // there shares the return.
      const Eigen::Vector3f u = dir_s.unitOrthogonal(), v = dir_s.cross(u);
      const double phi = 2.0 * M_PI * hash_uniform(mix64(h + 3));
      const float half = float(std::tan(0.5 * sensor.divergence));
      const Eigen::Vector3f rim = (dir_s + half * (float(std::cos(phi)) * u + float(std::sin(phi)) * v)).normalized();
      const Hit other = cast(R, origin, rim);
      if (other.t > 0 && std::abs(other.t - hit.t) > 0.05f)
        true_range = hit.t + hash_uniform(mix64(h + 4)) * double(other.t - hit.t);
    }
    const double range = true_range + sensor.range_sigma * hash_normal(mix64(h + 1));
    if (range < sensor.min_range || range > sensor.max_range) continue;
    // Calibrated reflectivity: Lambertian in the incidence angle, 5% noise.
    const double value = 255.0 * hit.reflectivity * std::max(0.05f, cos_inc) * (1.0 + 0.05 * hash_normal(mix64(h + 2)));
    xyz[r] = dir_s * float(range);
    time[r] = float(fraction * options.sweep_period);
    intensity[r] = float(std::clamp(value, 0.0, 255.0));
    label[r] = hit.label;
    valid[r] = 1;
  }

  PointSet out;
  const size_t n = size_t(std::count(valid.begin(), valid.end(), uint8_t(1)));
  out.xyz.reserve(n);
  out.intensity.reserve(n);
  out.label.reserve(n);
  for (size_t r = 0; r < rays; ++r) {
    if (!valid[r]) continue;
    out.xyz.push_back(xyz[r]);
    out.intensity.push_back(intensity[r]);
    out.label.push_back(label[r]);
    out.index.push_back(uint32_t(out.index.size()));
    if (options.times) options.times->push_back(time[r]);
  }
  out.scan.assign(out.size(), options.scan_id);
  return out;
}

}  // namespace lista::sim
