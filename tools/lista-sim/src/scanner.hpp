// One LiDAR sweep: rays from the sensor model cast into a static and an
// optional dynamic scene, with range noise, dropouts and intensity.
#pragma once

#include "raycaster.hpp"
#include "sensor.hpp"

#include <lista/points.hpp>

#include <cstdint>

namespace lista::sim {

struct SweepOptions {
  uint64_t key = 0;  // seeds the per-ray noise (hash of seed, mission, scan)
  int threads = 1;
  uint32_t scan_id = 0;  // provenance written into PointSet::scan
  // A legged robot's back under the sensor, moving with it (body_box_min /
  // body_box_max, sensor frame): hit like any surface, label 0.
  bool body = false;
  // Mixed pixels: where the beam's footprint (SensorModel::divergence, so
  // wider with range) straddles a depth edge, the return lands anywhere
  // between the two surfaces (a point in the air), as real LiDARs give.
  bool mixed_pixels = false;
  // Dark and grazing returns fade with range: a return whose signal
  // (reflectivity x cos(incidence) / range^2, against a 10 % target met
  // head-on at SensorModel::range_dark) is below that is lost in proportion.
  bool dark_dropouts = false;
  // A sweep takes time (sweep_period): ray r is cast at r / rays of it, from
  // the pose between T_world_sensor and *sweep_end (interpolated), and its
  // point is given in the sensor frame of that moment, as a driver delivers
  // it: a moving sensor's scan comes out skewed. Null: all rays at once.
  const Eigen::Isometry3d* sweep_end = nullptr;
  double sweep_period = 0.1;  // s
  std::vector<float>* times = nullptr;  // when set: each point's time after the sweep's start, s
};

// The robot's back of SweepOptions::body: 1.1 x 0.5 m, its top 0.15 m and its
// bottom 0.45 m below the sensor, reaching 0.9 m behind it and 0.2 m ahead.
inline const Eigen::Vector3f body_box_min{-0.9f, -0.25f, -0.45f};
inline const Eigen::Vector3f body_box_max{0.2f, 0.25f, -0.15f};

// Points in the SENSOR frame with intensity (0..255) and label (object id).
PointSet sweep(const RayScene& scene, const RayScene* dynamic_scene, const SensorModel& sensor,
               const Eigen::Isometry3d& T_world_sensor, const SweepOptions& options);

}  // namespace lista::sim
