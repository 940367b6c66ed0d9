// A 3-D pose graph optimised with Ceres: nodes are sensor poses in the common
// frame, edges relative-pose measurements (odometry between consecutive scans,
// loop closures between missions). Rotation on the quaternion manifold,
// translation Euclidean; loop closures under a robust loss.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace lista::align {

struct PoseGraphEdge {
  size_t from = 0, to = 0;
  Eigen::Isometry3d measurement = Eigen::Isometry3d::Identity();  // T_from_to
  double sigma_translation = 0.05;  // m
  double sigma_rotation = 0.01;     // rad
  // Only x, y (in the `from` sensor frame) and yaw: for measurements weak in
  // height and level (scan-to-scan registration of sparse scans, whose small
  // roll/pitch errors would tilt the map by tenths of a degree).
  bool planar = false;
  // Height (z) and level (roll, pitch) at sigmas of their own, for a
  // measurement weaker there than in x, y and yaw; 0: sigma_translation /
  // sigma_rotation.
  double sigma_height = 0.0, sigma_tilt = 0.0;
  bool robust = false;              // under the robust loss (loop closures)
};

enum class RobustLoss { cauchy, huber, none };

struct PoseGraphOptions {
  RobustLoss loss = RobustLoss::cauchy;
  double loss_scale = 1.0;      // in units of sigma
  int max_iterations = 100;
};

struct PoseGraphSummary {
  double initial_cost = 0.0, final_cost = 0.0;
  int iterations = 0;
  bool usable = false;  // Ceres ended with a usable solution
};

// Optimises `nodes` in place; nodes with fixed[i] stay put. At least one node
// must be fixed (the gauge).
PoseGraphSummary optimise_pose_graph(std::vector<Eigen::Isometry3d>& nodes, const std::vector<bool>& fixed,
                                     const std::vector<PoseGraphEdge>& edges, const PoseGraphOptions& options);

}  // namespace lista::align
