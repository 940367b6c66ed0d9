// A scan's points binned by direction, and what the scan saw of a surface
// patch another scan placed: present, seen through, or nothing. Internal to
// filter.body.
#pragma once

#include <lista/points.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace lista::filter {

// One scan's points binned by direction (azimuth 0.5 deg, elevation 1 deg),
// in compressed rows: the points of bin b are points[offsets[b] .. offsets[b+1]).
class RangeImage {
 public:
  static constexpr int kAz = 720, kEl = 180;

  explicit RangeImage(const PointSet& cloud);

  enum class Vote { none, present, see_through };

  // What this scan saw of a small surface patch (centre c, unit normal n
  // pointing to the side the patch was seen from; sensor frame). A real
  // surface is opaque: no ray passes behind it. So one of this scan's rays
  // that passes within `rho` of the point `depth` behind the patch and ends
  // more than `margin` beyond that point saw through where the patch was;
  // one that ends within `rho` of the patch's centre sees it present (that
  // wins). Rays that end short of both, or none at all, give no vote. Edge-on
  // views (the top of a robot's back from another scan at the same height)
  // work as well as head-on ones.
  Vote look(const Eigen::Vector3d& c, const Eigen::Vector3d& n, double depth, double rho, double margin) const;

 private:
  static int az_bin(const Eigen::Vector3d& q);
  static int el_bin(const Eigen::Vector3d& q);

  std::vector<uint32_t> offsets_;
  std::vector<Eigen::Vector3f> points_;
};

}  // namespace lista::filter
