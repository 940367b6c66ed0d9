// Applies a pairwise registration to every moved object of a Matches value:
// each pair is registered once and the partner gets the inverse, so the two
// transforms of a pair are exact inverses. Used by register.svd and register.icp.
#pragma once

#include <lista/context.hpp>
#include <lista/matches.hpp>
#include <lista/objects.hpp>

#include <Eigen/Geometry>
#include <functional>

namespace lista::registration {

// Maps source object points onto the target object: p_t = T * p_s.
using PairRegistration = std::function<Eigen::Isometry3d(const Object& source, const Object& target)>;

// Copies `matches`, filling transform/has_transform of every moved object
// whose partner is in `objects`. Pairs run in parallel on context.threads().
Matches register_matches(const ObjectSet& objects, const Matches& matches, const PairRegistration& reg,
                         Context& context);

}  // namespace lista::registration
