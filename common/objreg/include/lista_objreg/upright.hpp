// The floor gate shared by match.weighted and register.icp: an object that
// stands on the floor in both missions was moved on it, so a registration
// of the one onto the other keeps it upright.
#pragma once

#include <lista/objects.hpp>

#include <Eigen/Geometry>

namespace lista::objreg {

// True when `t` (mapping a's points onto b's) lifts a's centroid, relative
// to the two floors (Object::floor_z), by at most `max_lift` (0 = no lift
// check) and tilts it by at most `max_tilt_deg`. True when either floor is
// unknown (NaN).
bool stays_on_floor(const Object& a, const Object& b, const Eigen::Isometry3d& t, double max_lift,
                    double max_tilt_deg);

// The height a move on the floor lifts `a` by to stand where `b` stands:
// b.floor_z - a.floor_z; NaN when either floor is unknown.
double floor_lift(const Object& a, const Object& b);

}  // namespace lista::objreg
