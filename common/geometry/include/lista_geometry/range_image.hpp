// A scan's points binned by direction, and what the scan saw of a surface
// patch another scan placed: present, seen through, or nothing. Used by
// filter.body (the robot's body, which other scans see through) and by the
// volumetric stages (what moved during a mission).
#pragma once

#include <lista/points.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace lista::geometry {

// One scan's points binned by direction (azimuth 0.5 deg, elevation 1 deg),
// in compressed rows: the points of bin b are points[offsets[b] .. offsets[b+1]).
class RangeImage {
 public:
  static constexpr int kAz = 720, kEl = 180;

  explicit RangeImage(const PointSet& cloud) : offsets_(size_t(kAz) * kEl + 1, 0) {
    std::vector<uint32_t> bin(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) {
      const Eigen::Vector3d q = cloud.xyz[i].cast<double>();
      bin[i] = uint32_t(el_bin(q) * kAz + az_bin(q));
      ++offsets_[bin[i] + 1];
    }
    for (size_t b = 1; b < offsets_.size(); ++b) offsets_[b] += offsets_[b - 1];
    points_.resize(cloud.size());
    std::vector<uint32_t> fill(offsets_.begin(), offsets_.end() - 1);
    for (size_t i = 0; i < cloud.size(); ++i) points_[fill[bin[i]]++] = cloud.xyz[i];
  }

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
  Vote look(const Eigen::Vector3d& c, const Eigen::Vector3d& n, double depth, double rho, double margin) const {
    const Eigen::Vector3d q = c - depth * n;
    const double r = q.norm();
    if (r < 1e-6) return Vote::none;
    const double reach = std::atan2(rho + depth, r) * 180.0 / M_PI;
    const double cos_el = std::max(0.05, std::sqrt(std::max(0.0, 1.0 - (q.z() / r) * (q.z() / r))));
    const int half_az = std::min(60, int(std::ceil(reach / cos_el * 2.0)) + 1);
    const int half_el = std::min(30, int(std::ceil(reach)) + 1);
    const int az = az_bin(q), el = el_bin(q);
    bool through = false;
    // Bins nearest the point's direction first: a surface really there is
    // usually found present within a few bins, ending the search.
    for (int ring = 0; ring <= std::max(half_az, half_el); ++ring)
      for (int de = -std::min(ring, half_el); de <= std::min(ring, half_el); ++de) {
        const int e = el + de;
        if (e < 0 || e >= kEl) continue;
        const bool edge_row = std::abs(de) == ring;
        for (int da = -std::min(ring, half_az); da <= std::min(ring, half_az); ++da) {
          if (!edge_row && std::abs(da) != ring) continue;  // inner bins were searched in earlier rings
          const size_t b = size_t(e) * kAz + size_t((az + da + 10 * kAz) % kAz);
          for (uint32_t k = offsets_[b]; k < offsets_[b + 1]; ++k) {
            const Eigen::Vector3d p = points_[k].cast<double>();
            if ((p - c).squaredNorm() <= rho * rho) return Vote::present;
            const double range = p.norm();
            if (range < 1e-6) continue;
            const Eigen::Vector3d u = p / range;
            const double t = u.dot(q);
            if (t <= 0 || range <= t + margin) continue;
            if ((q - t * u).squaredNorm() <= rho * rho) through = true;
          }
        }
      }
    return through ? Vote::see_through : Vote::none;
  }

 private:
  static int az_bin(const Eigen::Vector3d& q) {
    double deg = std::atan2(q.y(), q.x()) * 180.0 / M_PI;
    if (deg < 0) deg += 360.0;
    return std::min(kAz - 1, int(deg * 2.0));
  }
  static int el_bin(const Eigen::Vector3d& q) {
    const double r = std::max(q.norm(), 1e-9);
    const double deg = std::asin(std::clamp(q.z() / r, -1.0, 1.0)) * 180.0 / M_PI;
    return std::clamp(int(std::floor(deg + 90.0)), 0, kEl - 1);
  }

  std::vector<uint32_t> offsets_;
  std::vector<Eigen::Vector3f> points_;
};

}  // namespace lista::geometry
