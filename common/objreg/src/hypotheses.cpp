#include "hypotheses.hpp"

#include <lista_geometry/bounding_rectangle.hpp>

#include <algorithm>
#include <array>
#include <cmath>

namespace lista::objreg {

std::vector<Eigen::Isometry3d> centroid_starts(const PrincipalFrame& fs, const PrincipalFrame& ft,
                                               const IcpConfig& cfg) {
  std::vector<Eigen::Isometry3d> guesses;
  if (cfg.svd_flips) {
    for (const Eigen::Matrix3d& flip : axis_flips()) {
      Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
      f.linear() = flip;
      guesses.push_back(ft.frame * f * fs.frame.inverse());
    }
  } else {
    guesses.push_back(svd_transform(fs, ft));
  }
  const Eigen::Vector3d cs = fs.frame.translation(), ct = ft.frame.translation();
  for (int k = 0; k < cfg.yaw_hypotheses; ++k) {
    Eigen::Isometry3d g = Eigen::Isometry3d::Identity();
    g.linear() = Eigen::AngleAxisd(2.0 * M_PI * k / cfg.yaw_hypotheses, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    g.translation() = ct - g.linear() * cs;
    if (std::isfinite(cfg.floor_lift)) g.translation().z() = cfg.floor_lift;  // base onto base
    guesses.push_back(g);
  }
  return guesses;
}

std::vector<Eigen::Isometry3d> corner_starts(const std::vector<Eigen::Vector3f>& source,
                                             const std::vector<Eigen::Vector3f>& target, double lift, double slack) {
  const geometry::BoundingRectangle rs = geometry::min_perimeter_rectangle(source),
                                    rt = geometry::min_perimeter_rectangle(target);
  if (!rs.valid || !rt.valid) return {};
  if (std::abs(rs.long_side - rt.long_side) <= slack && std::abs(rs.short_side - rt.short_side) <= slack) return {};
  const std::array<Eigen::Vector2d, 4> source_corners = rs.corners(), target_corners = rt.corners();
  std::vector<Eigen::Isometry3d> out;
  const double base = std::atan2(rt.long_axis.y(), rt.long_axis.x()) - std::atan2(rs.long_axis.y(), rs.long_axis.x());
  for (int quarter = 0; quarter < 4; ++quarter) {
    const Eigen::Matrix2d r = Eigen::Rotation2Dd(base + quarter * M_PI / 2).toRotationMatrix();
    size_t n_this_turn = 0;
    for (const Eigen::Vector2d& tc : target_corners) {
      // The source corner lying, once turned, in the same quadrant of its
      // rectangle as tc does in the target's.
      int best = 0;
      double best_dot = -INFINITY;
      for (int k = 0; k < 4; ++k)
        if (const double d = (r * (source_corners[k] - rs.centre)).dot(tc - rt.centre); d > best_dot) best_dot = d, best = k;
      const Eigen::Vector2d t = tc - r * source_corners[best];
      // Footprints of one length along an axis put two corners at nearly
      // the same start: one is enough.
      if (std::any_of(out.end() - int(n_this_turn), out.end(), [&](const Eigen::Isometry3d& g) {
            return (g.translation().head<2>() - t).norm() <= slack;
          }))
        continue;
      Eigen::Isometry3d g = Eigen::Isometry3d::Identity();
      g.linear().topLeftCorner<2, 2>() = r;
      g.translation().head<2>() = t;
      g.translation().z() = lift;
      out.push_back(g);
      ++n_this_turn;
    }
  }
  return out;
}

}  // namespace lista::objreg
