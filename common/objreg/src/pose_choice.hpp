// Which of an object pair's refined poses wins, and which others tie with
// it (IcpResult::alternatives). Internal to lista_objreg (icp_refine.cpp).
#pragma once

#include "pair_icp.hpp"

#include <vector>

namespace lista::objreg {

// The rotation angle of a pose (radians).
double turn_of(const Eigen::Isometry3d& t);

// Near-symmetric shapes (boxes, cabinets) fit equally well turned by 180
// degrees; among poses scoring within symmetry_tolerance of the best, the
// one with the smallest rotation is the simplest explanation of the move.
// With `constrained`, among cfg.admissible's poses when there are any.
// Returns its index in `cs`.
size_t simplest_best(const std::vector<Candidate>& cs, const IcpConfig& cfg, bool constrained = true);

// Two poses of the same source are distinct when they differ by at least
// distinct_degrees of rotation or distinct_metres at the source centroid `c`.
bool distinct_poses(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, const Eigen::Vector3d& c,
                    const IcpConfig& cfg);

// The candidates other than `win` that tie with it (score within
// symmetry_tolerance of the best) and are distinct poses: turned by at least
// distinct_degrees or shifted by at least distinct_metres at the source
// centroid `c`, from the winner and from every alternative kept before them
// (best score first).
std::vector<Eigen::Isometry3d> distinct_ties(const std::vector<Candidate>& cs, size_t win, const Eigen::Vector3d& c,
                                             const IcpConfig& cfg);

}  // namespace lista::objreg
