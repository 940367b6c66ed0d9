// ICP refinement of an object pair from several initial hypotheses.
//
// Hypotheses: the SVD principal-frame guess with its four proper axis flips
// (what symmetric shapes leave undecided) and `yaw_hypotheses` rotations about
// the vertical through the centroids (objects are mostly moved on the floor);
// with corner_hypotheses, when the two footprints (minimum-perimeter
// rectangles) differ in a side by more than 0.1 m and no coarse pose from
// those starts placed 90 % of the moved view within inlier_distance (in an
// admissible pose, when `admissible` is set), also poses that put a corner
// of one footprint on a corner of the other, sides parallel: a partial view
// (half a table, two faces of a container) shares a corner with the whole
// object, not its centre. Of those (up to 16) the 4 scoring best as they
// stand are registered.
// Each is refined with PCL's Generalized ICP (or point-to-point ICP) and
// scored by the truncated mean squared distance of the moved source points to
// the target, min(d^2, inlier^2), computed both ways so that a partial view
// cannot hide inside a larger one. The three best are refined again with
// the correspondence gate narrowed to inlier_distance (a wide gate lets a
// partial view bias the pose), and with GICP a point-to-point ICP polish of
// each competes (GICP's minimum can sit degrees off on box-like objects);
// the lowest score wins, except that among
// poses within symmetry_tolerance of it the smallest rotation wins
// (symmetric shapes fit as well turned by 180 degrees). The other poses
// within symmetry_tolerance that differ from the winner by more than
// distinct_degrees or distinct_metres are returned as alternatives: the
// pose is ambiguous (a box's half-turn, a barrel's any turn), and a user
// reading the transform should know. An alternative A = S * T shows a
// symmetry S of the target; S^2 * T ... (up to S^7) are scored too, so a
// square crate lists all three other quarter turns.
//
// Cost: large objects (tens of thousands of points) iterate the coarse pass
// on an evenly strided subset (max_points) and the fine pass on a larger one
// (fine_max_points), which first runs the wide gate again: a pose found from
// few points can sit slid along a large face, beyond the narrow gate's reach.
//
// Direction: ICP pulls every moving point towards the fixed cloud, so a
// moving cloud with parts the other never saw is dragged off. The cloud
// covering fewer voxels (mostly a partial view) is registered onto the other
// and the result inverted; the returned transform always maps source onto
// target. Searches use lista_pcl's FastKdTree (see fast_kdtree.hpp).
#pragma once

#include <lista/points.hpp>

#include <Eigen/Geometry>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace lista::objreg {

enum class PairMethod { gicp, icp };

struct IcpConfig {
  PairMethod method = PairMethod::gicp;
  double voxel = 0.02;                // m: downsampling before ICP; 0 = none
  double max_correspondence = 0.15;   // m
  int max_iterations = 50;
  int yaw_hypotheses = 8;             // 0 = none
  bool svd_flips = true;              // try the SVD guess's four axis flips
  bool corner_hypotheses = true;      // footprints of different sizes: also start corner on corner
  double inlier_distance = 0.05;      // m: truncation of the score
  double symmetry_tolerance = 0.1;    // poses within this share of the best score tie; smallest rotation wins
  double distinct_degrees = 10.0;     // a tying pose turned at least this far from the winner is an alternative
  double distinct_metres = 0.1;       // ... or shifted at least this far (at the source centroid)
  bool list_alternatives = true;      // false: no alternatives sought (their scoring costs; a fit check needs none)
  int max_points = 2000;              // the coarse pass (every hypothesis) iterates on at most this many
                                      // source points (strided); 0 = all
  int fine_max_points = 8000;         // the fine pass on the few best: at most this many, never fewer
                                      // than max_points; 0 = all, < 0 = as max_points
  int max_score_points = 10000;       // scores query at most this many points each way (strided; the
                                      // searched cloud stays whole); 0 = all
  // Poses (source onto target) the caller can accept, e.g. upright for two
  // objects standing on floors. When set, the best admissible pose wins
  // over better-scoring inadmissible ones, and only admissible poses are
  // listed as alternatives; if no refined pose is admissible the best one
  // is returned as without it. Empty: every pose.
  std::function<bool(const Eigen::Isometry3d&)> admissible;
  // Height (m) a pose keeping both objects on their floors lifts the source
  // by: the target's floor minus the source's (objreg::floor_lift).
  // When finite, the yaw hypotheses start at this height instead of at the
  // centroids': a view missing its top (a container's upper metre the other
  // mission never saw free) has its centroid lower than the whole object's,
  // and ICP along vertical faces cannot pull it back down. NaN: centroids.
  double floor_lift = std::numeric_limits<double>::quiet_NaN();
};

struct IcpResult {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // p_target = T * p_source
  double score = 0.0;        // truncated mean squared distance (m^2), lower is better
  double inlier_ratio = 0.0; // share of points within inlier_distance (both ways averaged)
  double source_inliers = 0.0;  // share of moved source points within inlier_distance of the target
  double target_inliers = 0.0;  // share of target points within inlier_distance of the moved source
  int hypotheses = 0;
  // True when, without IcpConfig::admissible, another (inadmissible) pose
  // would have been chosen: the constraint decided.
  bool inadmissible_preferred = false;
  // Other poses scoring within symmetry_tolerance of `transform`, each at
  // least distinct_degrees / distinct_metres from it and from one another,
  // best first; empty when the pose is unambiguous.
  std::vector<Eigen::Isometry3d> alternatives;
};

// The settings of a quick shape check of two objects (is one rigid object
// both?): point-to-point ICP on `voxel`-downsampled views, a gate wide
// enough (3 x inlier_distance, at least 0.3 m) to pull a partial view into
// place, at most 400 points iterated and 2000 scored, yaw turns without the
// SVD guess's flips (objects stand on floors), no alternatives listed.
// match.weighted's shape check and segment.complete's still check use it.
IcpConfig shape_check_config(double voxel, double inlier_distance);

IcpResult icp_refine(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                     const IcpConfig& cfg);

}  // namespace lista::objreg
