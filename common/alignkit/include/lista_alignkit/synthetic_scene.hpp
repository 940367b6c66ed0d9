// Test-only: a synthetic indoor scene of axis-aligned boxes (walls, floor,
// ceiling, furniture) and a ray-cast spinning LiDAR, so alignment tests run
// on scans with real occlusion and sparsity without any data files.
#pragma once

#include <lista/missions.hpp>

#include <Eigen/Geometry>
#include <random>
#include <vector>

namespace lista::alignkit::testing {

struct Box {
  Eigen::Vector3d min, max;
};

struct Scene {
  std::vector<Box> boxes;
};

// A hall of size x size_y with walls, floor, ceiling (3 m) and `furniture`
// random boxes placed away from the loop route.
Scene make_hall(double size_x, double size_y, int furniture, uint32_t seed);
// An open field: ground only with a few thin poles (nothing like a hall).
Scene make_field(uint32_t seed);

// Points (sensor frame) seen from `pose` by a spinning LiDAR with `rings`
// beams between -15 and +15 degrees, 1 degree azimuth steps, 40 m range.
PointSet cast_scan(const Scene& scene, const Eigen::Isometry3d& pose, uint32_t scan_index, std::mt19937& rng,
                   int rings = 16);

// Sensor poses (1 m above the floor) every `step` metres around a rectangular
// loop inset `inset` metres from the hall walls, starting `phase` metres along it.
std::vector<Eigen::Isometry3d> loop_route(double size_x, double size_y, double inset, double step, double phase,
                                          double lateral = 0.0);

// Odometry with drift: each relative motion turned by yaw_rate * length and
// scaled by (1 + scale_error), then the whole chain put in a map frame whose
// origin is `map_from_world` (a random start offset).
std::vector<Eigen::Isometry3d> drifted(const std::vector<Eigen::Isometry3d>& truth, double yaw_rate,
                                       double scale_error, const Eigen::Isometry3d& map_from_world);

// A mission read from nowhere: poses (map frame), poses_gt (truth) and scans
// by a `rings`-beam sensor (cast_scan).
Mission make_mission(const std::string& name, const Scene& scene, const std::vector<Eigen::Isometry3d>& truth,
                     const std::vector<Eigen::Isometry3d>& poses, uint32_t seed, int rings = 16);

}  // namespace lista::alignkit::testing
