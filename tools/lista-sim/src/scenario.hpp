// What is where in each mission: the object instances, their world poses per
// mission (the ground truth), the changes between consecutive missions, the
// people walking through, and each mission's route, true poses and drifted
// odometry poses.
#pragma once

#include "footprint.hpp"
#include "layout.hpp"
#include "shapes.hpp"

#include <Eigen/Geometry>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace lista::sim {

// How the changes of one mission relate to each other.
enum class ChangeSpacing {
  any,       // placed independently
  separate,  // changed objects keep >= 1 m from every other change (exp2)
  overlap    // changes are placed on or next to other changes (exp3)
};

struct ChangeParams {
  int objects = 10;        // objects in the first mission
  int duplicates = 2;      // extra copies of already used shapes (identical objects)
  int moves = 2;           // per later mission
  int short_moves = 1;     // of those, moves shorter than the object's size
  int swaps = 1;           // swapped pairs of identical objects
  int removals = 1;
  int additions = 1;
  int people = 1;          // people walking through each mission
  bool station_operator = false;  // a person standing beside the sensor at each scan (a surveyor)
  ChangeSpacing spacing = ChangeSpacing::any;
  std::vector<std::string> classes;  // object classes to draw from
  std::vector<Shape> extra_shapes;   // loaded meshes (sweethome3d) also drawn from
};

struct RouteParams {
  int missions = 2;
  int scans = 20;              // scans per mission, spread along the route
  double deviation = 0.12;     // max lateral deviation of later missions from the first, m
  double drift_per_m = 0.002;  // translation drift rate (fraction of distance)
  double yaw_drift_deg_per_m = 0.01;
  // Each mission's map frame tilted by this in a random direction (a SLAM
  // run started on a slope, a handheld scanner's first frame); 0 = level.
  double map_tilt_deg = 0.0;
  // The sensor also turns about its own up axis at this rate (scans 0.1 s
  // apart): a robot turning on the spot, a rotating mount; 0 = as the route.
  double spin_deg_per_s = 0.0;
};

struct Person {
  uint32_t id = 0;
  int shape = 0;
  Eigen::Vector2d from, to;  // walks from -> to and back during the mission
  double phase = 0.0;
  // Stands beside the sensor instead, a little behind it, facing it, at a
  // place that changes from scan to scan (the operator of a tripod scanner).
  bool beside_sensor = false;
};

struct MissionPlan {
  std::string name;
  std::map<uint32_t, Eigen::Isometry3d> objects;  // object id -> world pose (present objects)
  std::vector<Person> people;
  std::vector<Eigen::Isometry3d> poses_true;      // T_world_sensor per scan
  std::vector<Eigen::Isometry3d> poses_estimated; // T_map_sensor per scan (with drift)
  Eigen::Isometry3d map_to_world = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d person_pose(const Person& p, size_t scan) const;
};

struct Scenario {
  Layout layout;
  std::vector<Shape> shapes;
  std::map<uint32_t, int> object_shape;  // object id -> shape index (people included)
  std::vector<MissionPlan> missions;
  // For logs: every change of each object, mission by mission ("moved",
  // "swapped", ...); with 3+ missions an object can change more than once.
  std::map<uint32_t, std::vector<std::string>> change_kind;
};

// Footprint of a shape at a world pose.
Footprint footprint_of(const Shape& shape, const Eigen::Isometry3d& pose);

// Builds everything but the scans. Deterministic in `seed`.
Scenario plan_scenario(Layout layout, const ChangeParams& changes, const RouteParams& route, uint64_t seed);

}  // namespace lista::sim
