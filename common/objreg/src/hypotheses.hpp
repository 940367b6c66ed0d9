// Where the ICP of an object pair starts from: the principal frames and
// yaw turns through the centroids, and corner on corner for footprints of
// different sizes. Internal to lista_objreg (icp_refine.cpp).
#pragma once

#include <lista_objreg/icp_refine.hpp>
#include <lista_objreg/svd_registration.hpp>

#include <Eigen/Geometry>

#include <vector>

namespace lista::objreg {

// The SVD principal-frame guess (with its four proper axis flips when
// cfg.svd_flips) and cfg.yaw_hypotheses turns about the vertical through the
// centroids, at cfg.floor_lift when it is finite (base onto base).
std::vector<Eigen::Isometry3d> centroid_starts(const PrincipalFrame& source, const PrincipalFrame& target,
                                               const IcpConfig& cfg);

// Starts that put a corner of the source's footprint on a corner of the
// target's, the rectangles' sides parallel (four quarter turns x four
// corners): a partial view (half a table, two faces of a container) shares
// a corner with the whole, not its centre. Empty when the footprints agree
// in size within `slack` (then the centroid starts cover it); of one turn's
// starts less than `slack` apart only the first is kept.
std::vector<Eigen::Isometry3d> corner_starts(const std::vector<Eigen::Vector3f>& source,
                                             const std::vector<Eigen::Vector3f>& target, double lift, double slack);

}  // namespace lista::objreg
