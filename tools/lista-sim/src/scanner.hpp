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
};

// Points in the SENSOR frame with intensity (0..255) and label (object id).
PointSet sweep(const RayScene& scene, const RayScene* dynamic_scene, const SensorModel& sensor,
               const Eigen::Isometry3d& T_world_sensor, const SweepOptions& options);

}  // namespace lista::sim
