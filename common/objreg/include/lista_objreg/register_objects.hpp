// Applies a pairwise registration to every moved object of a Matches value:
// each pair is registered once and the partner gets the inverse, so the two
// transforms of a pair are exact inverses. Used by register.svd and register.icp.
#pragma once

#include <lista/context.hpp>
#include <lista/matches.hpp>
#include <lista/objects.hpp>

#include <Eigen/Geometry>
#include <functional>
#include <vector>

namespace lista::objreg {

// What a pairwise registration found: p_t = transform * p_s, and the other
// poses that fit about as well (empty: unambiguous).
struct PairPose {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> alternatives;
};

// Maps source object points onto the target object.
using PairRegistration = std::function<PairPose(const Object& source, const Object& target)>;

// Copies `matches`, filling transform/has_transform/alternative_transforms of
// every moved object whose partner is in `objects` (the partner gets the
// inverses). Pairs run in parallel on context.threads().
Matches register_matches(const ObjectSet& objects, const Matches& matches, const PairRegistration& reg,
                         Context& context);

}  // namespace lista::objreg
