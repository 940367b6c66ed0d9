// The cost of every candidate pair between two consecutive missions'
// changed objects (distance, descriptor, shape misfit, group penalty) and
// the gates that refuse a pair. Internal to match.weighted.
#pragma once

#include "weighted_matcher.hpp"

#include <Eigen/Core>

#include <vector>

namespace lista::match {

using BoolMatrix = Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>;

// Rows: the earlier mission's objects `a`, columns: the later's `b`.
struct PairCosts {
  Eigen::MatrixXd physical, descriptor, shape, weighted;
  Eigen::MatrixXd cross;  // the group penalty part of `weighted`
  BoolMatrix allowed;
};

// The largest descriptor distance between any two objects of the scene: the
// descriptor scale for "max" normalisation, so that noise between
// near-identical objects stays small next to real class differences.
double descriptor_scale(const ObjectSet& objects, const DescriptorSet& desc);

// `a_changed[i]` / `b_changed[j]`: the object changed against the other
// mission (a pair needs one of the two). Shape fits come from `fit`, for
// the pairs every other gate allowed.
PairCosts pair_costs(const std::vector<const Object*>& a, const std::vector<const Object*>& b,
                     const DescriptorSet& desc, const Groups* groups, const WeightedMatchConfig& cfg,
                     double desc_scale, const PairFit& fit, const std::vector<bool>& a_changed,
                     const std::vector<bool>& b_changed);

}  // namespace lista::match
