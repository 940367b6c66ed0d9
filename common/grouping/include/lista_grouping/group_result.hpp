// Turns a clustering (one label per descriptor row) into lista::Groups with
// the paper's confidences. Shared by group.kmeans and group.agglomerative so
// both report confidence the same way.
//
// Cluster confidence (paper, sect. "Correspondence grouping"): the mean L2
// distance of a cluster's descriptors to its centroid, min-max normalised over
// all clusters, is 0 for the most compact cluster and 1 for the most
// dispersed. The report wants 1 = most confident, so
//   group_confidence = 1 - (mean_i - mean_min) / (mean_max - mean_min)
// (1 for every cluster when all means are equal, e.g. a single cluster).
// Object confidence: the object's distance to its own centroid, normalised by
// the largest such distance over all objects,
//   confidence = 1 - d_i / d_max   (1 for all when d_max = 0),
// so the object at the heart of its class gets 1 and the worst outlier 0.
#pragma once

#include <lista/descriptors.hpp>
#include <lista/groups.hpp>

#include <Eigen/Core>
#include <string>
#include <vector>

namespace lista::grouping {

// Descriptor rows as doubles (clustering is done in double precision).
Eigen::MatrixXd to_double(const DescriptorSet& d);

// Labels must be 0..k-1 with every label used at least once.
Groups make_groups(const std::string& method, const std::vector<int>& object_ids,
                   const Eigen::MatrixXd& x, const std::vector<int>& labels);

// Throws lista::Error for an unusable descriptor set (row count mismatch,
// non-finite values).
void check_descriptors(const DescriptorSet& d);

}  // namespace lista::grouping
