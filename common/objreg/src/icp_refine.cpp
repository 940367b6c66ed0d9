// Object-pair ICP (PCL); used by register.icp and match.weighted.
#include <lista_objreg/icp_refine.hpp>

#include <lista_objreg/svd_registration.hpp>

#include "voxel_cloud.hpp"

#include <lista/error.hpp>
#include <lista_geometry/bounding_rectangle.hpp>
#include <lista_pcl/fast_kdtree.hpp>
#include <lista_pcl/quiet.hpp>

#include <pcl/registration/gicp.h>
#include <pcl/registration/icp.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lista::registration {

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// Truncated mean squared nearest-neighbour distance of T*from to `to`, over
// at most max_points evenly strided points of `from` (0 = all).
double one_way(const Cloud& from, const pcl_search::FastKdTree& to_tree, const Eigen::Isometry3d& t,
               double inlier, int max_points, double& inlier_share) {
  const double cap = inlier * inlier;
  double sum = 0.0;
  size_t inliers = 0, used = 0;
  const Eigen::Isometry3f tf = t.cast<float>();
  const double step = max_points > 0 && from.size() > static_cast<size_t>(max_points)
                          ? static_cast<double>(from.size()) / max_points : 1.0;
  for (double k = 0.0; k < static_cast<double>(from.size()); k += step, ++used) {
    const Eigen::Vector3f q = tf * from[static_cast<size_t>(k)].getVector3fMap();
    // Farther than the inlier distance counts as the cap: searched no farther.
    float d2 = 0.0f;
    const double d = to_tree.nearest(pcl::PointXYZ(q.x(), q.y(), q.z()), d2, static_cast<float>(cap)) < 0
                         ? cap : std::min<double>(d2, cap);
    if (d < cap) ++inliers;
    sum += d;
  }
  inlier_share = used == 0 ? 0.0 : static_cast<double>(inliers) / used;
  return used == 0 ? cap : sum / used;
}

// Powers of a symmetry tried for further alternatives: up to S^7 (an
// octagon's turns; a round shape's list stops there).
constexpr int kMaxSymmetryPower = 8;

// Footprints whose sides agree within this (m) are views of the same extent:
// no corner starts.
constexpr double kCornerSlack = 0.1;
// A coarse pose placing this share of the moved view within the inlier
// distance of the other explains it: no corner starts are tried.
constexpr double kExplainedShare = 0.9;
// Of the (up to 16) corner starts, only this many, the best scored as they
// stand, get a coarse ICP run: the right corner already lays the view on
// the other's surface, and each run costs as much as a whole centroid start.
constexpr size_t kCornerStartsRegistered = 4;

// Starts that put a corner of the source's footprint on a corner of the
// target's, the rectangles' sides parallel (four quarter turns x four
// corners): a partial view (half a table, two faces of a container) shares
// a corner with the whole, not its centre. Empty when the footprints agree
// in size within `slack` (then the centroid starts cover it); of one turn's
// starts less than `slack` apart only the first is kept.
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

struct Candidate {
  Eigen::Isometry3d t;
  double score, in_source, in_target;
};

// Two poses of the same source are distinct when they differ by at least
// distinct_degrees of rotation or distinct_metres at the source centroid `c`.
bool distinct_poses(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, const Eigen::Vector3d& c,
                    const IcpConfig& cfg) {
  const double degrees = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
  return degrees >= cfg.distinct_degrees || (a * c - b * c).norm() >= cfg.distinct_metres;
}

// The candidates other than `win` that tie with it (score within
// symmetry_tolerance of the best) and are distinct poses: turned by at least
// distinct_degrees or shifted by at least distinct_metres at the source
// centroid `c`, from the winner and from every alternative kept before them
// (best score first).
std::vector<Eigen::Isometry3d> distinct_ties(const std::vector<Candidate>& cs, size_t win, const Eigen::Vector3d& c,
                                             const IcpConfig& cfg) {
  double best = cs[win].score;
  for (const Candidate& k : cs) best = std::min(best, k.score);
  const double limit = best * (1.0 + cfg.symmetry_tolerance);
  std::vector<size_t> order(cs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return cs[a].score < cs[b].score; });
  std::vector<Eigen::Isometry3d> kept{cs[win].t};
  for (size_t i : order) {
    if (i == win || cs[i].score > limit) continue;
    if (std::all_of(kept.begin(), kept.end(), [&](const Eigen::Isometry3d& k) { return distinct_poses(k, cs[i].t, c, cfg); }))
      kept.push_back(cs[i].t);
  }
  kept.erase(kept.begin());
  return kept;
}

// Registers `source` onto `target` (their voxelised clouds `src`, `dst`).
IcpResult refine_pair(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                      const Cloud::Ptr& src, const Cloud::Ptr& dst, const IcpConfig& cfg) {
  // ICP's cost is one target search per source point and iteration: the
  // coarse pass over every hypothesis iterates on an evenly strided subset
  // (max_points), the fine pass on the few best on a larger one
  // (fine_max_points); scores search the whole voxelised clouds (querying at
  // most max_score_points each way).
  auto strided = [&](int max_points) {
    if (max_points <= 0 || src->size() <= static_cast<size_t>(max_points)) return src;
    Cloud::Ptr sub(new Cloud);
    const double step = static_cast<double>(src->size()) / max_points;
    for (int k = 0; k < max_points; ++k) sub->push_back((*src)[static_cast<size_t>(k * step)]);
    return sub;
  };
  // The fine pass never iterates on fewer points than the coarse one.
  int fine_points = cfg.fine_max_points < 0 ? cfg.max_points : cfg.fine_max_points;
  if (cfg.max_points <= 0) fine_points = 0;
  else if (fine_points > 0 && fine_points < cfg.max_points) fine_points = cfg.max_points;
  const Cloud::Ptr src_icp = strided(cfg.max_points);
  const Cloud::Ptr src_fine = fine_points == cfg.max_points ? src_icp : strided(fine_points);
  const bool fine_is_coarse = src_fine == src_icp;  // also when the source is small enough for both
  pcl_search::FastKdTree src_tree, dst_tree;
  src_tree.setInputCloud(src);
  dst_tree.setInputCloud(dst);

  // Initial hypotheses.
  const PrincipalFrame fs = principal_frame(source), ft = principal_frame(target);
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

  // GICP estimates local covariances from 20 neighbours: too few points,
  // plain ICP (decided per pass: the fine subset may be large enough).
  const bool gicp_method = cfg.method == "gicp" && dst->size() >= 30;
  bool use_gicp = gicp_method && src_icp->size() >= 30;
  // One registration object for all hypotheses: GICP then computes the
  // points' covariances once, not once per hypothesis.
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp;
  pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> icp;
  // Their target trees answer correspondence queries only within the gate.
  const auto gicp_target = std::make_shared<pcl_search::FastKdTree>(), icp_target = std::make_shared<pcl_search::FastKdTree>();
  if (gicp_method) {
    gicp.setSearchMethodSource(std::make_shared<pcl_search::FastKdTree>());
    gicp.setSearchMethodTarget(gicp_target);
    gicp.setInputSource(src_icp);
    gicp.setInputTarget(dst);
  }
  // Point-to-point ICP always: the method itself, or GICP's final polish.
  icp.setSearchMethodSource(std::make_shared<pcl_search::FastKdTree>());
  icp.setSearchMethodTarget(icp_target);
  icp.setInputSource(src_icp);
  icp.setInputTarget(dst);
  // The fine pass switches both registrations to src_fine once (GICP then
  // computes the larger subset's covariances once, not per hypothesis).
  auto use_fine_points = [&] {
    if (fine_is_coarse) return;
    use_gicp = gicp_method && src_fine->size() >= 30;
    if (use_gicp) gicp.setInputSource(src_fine);
    icp.setInputSource(src_fine);
  };
  auto refine = [&](const Eigen::Isometry3d& guess, double max_correspondence, bool point_to_point = false) {
    Cloud aligned;
    Eigen::Isometry3d t = guess;
    auto run = [&](auto& reg) {
      reg.setMaxCorrespondenceDistance(max_correspondence);
      const float gate = static_cast<float>(max_correspondence * max_correspondence);
      gicp_target->set_nearest_bound(gate);
      icp_target->set_nearest_bound(gate);
      reg.setMaximumIterations(cfg.max_iterations);
      reg.setTransformationEpsilon(1e-8);
      {
        pcl_convert::QuietPcl quiet;  // "not enough correspondences" is judged below, not printed
        reg.align(aligned, guess.matrix().cast<float>());
      }
      if (reg.hasConverged()) {
        Eigen::Matrix4d m = reg.getFinalTransformation().template cast<double>();
        // Re-orthonormalise: float accumulation drifts slightly from SO(3).
        Eigen::Quaterniond q(Eigen::Matrix3d(m.topLeftCorner<3, 3>()));
        t = Eigen::Isometry3d::Identity();
        t.linear() = q.normalized().toRotationMatrix();
        t.translation() = m.topRightCorner<3, 1>();
      }
    };
    if (use_gicp && !point_to_point) run(gicp);
    else run(icp);
    return t;
  };
  auto score_of = [&](const Eigen::Isometry3d& t, double& in_a, double& in_b) {
    return 0.5 * (one_way(*src, dst_tree, t, cfg.inlier_distance, cfg.max_score_points, in_a) +
                  one_way(*dst, src_tree, t.inverse(), cfg.inlier_distance, cfg.max_score_points, in_b));
  };

  // Coarse pass from every hypothesis with the wide correspondence distance.
  std::vector<Candidate> coarse;
  auto coarse_from = [&](const Eigen::Isometry3d& guess) {
    Candidate c{refine(guess, cfg.max_correspondence), 0.0, 0.0, 0.0};
    c.score = score_of(c.t, c.in_source, c.in_target);
    coarse.push_back(c);
  };
  for (const Eigen::Isometry3d& guess : guesses) coarse_from(guess);
  // Corner starts only where no centroid start explained the moved view
  // (the one covering fewer voxels) in a pose the caller accepts: they
  // cost as much again.
  const bool explained = std::any_of(coarse.begin(), coarse.end(), [&](const Candidate& c) {
    return c.in_source >= kExplainedShare && (!cfg.admissible || cfg.admissible(c.t));
  });
  if (cfg.corner_hypotheses && !explained) {
    const double lift = std::isfinite(cfg.floor_lift) ? cfg.floor_lift : ct.z() - cs.z();
    std::vector<std::pair<double, Eigen::Isometry3d>> starts;
    for (const Eigen::Isometry3d& g : corner_starts(source, target, lift, kCornerSlack)) {
      double in_a = 0.0, in_b = 0.0;
      starts.emplace_back(score_of(g, in_a, in_b), g);
    }
    std::stable_sort(starts.begin(), starts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    if (starts.size() > kCornerStartsRegistered) starts.resize(kCornerStartsRegistered);
    for (const auto& start : starts) {
      guesses.push_back(start.second);
      coarse_from(start.second);
    }
  }
  std::stable_sort(coarse.begin(), coarse.end(), [](const Candidate& a, const Candidate& b) { return a.score < b.score; });

  // Near-symmetric shapes (boxes, cabinets) fit equally well turned by 180
  // degrees; among poses scoring within symmetry_tolerance of the best, the
  // one with the smallest rotation is the simplest explanation of the move.
  auto angle = [](const Eigen::Isometry3d& t) { return Eigen::AngleAxisd(t.linear()).angle(); };
  // Among the admissible candidates when there are any (cfg.admissible).
  auto admissible = [&](const Candidate& c) { return !cfg.admissible || cfg.admissible(c.t); };
  auto pick = [&](const std::vector<Candidate>& cs, bool constrained = true) {
    const bool any = constrained && std::any_of(cs.begin(), cs.end(), admissible);
    auto eligible = [&](size_t i) { return !any || admissible(cs[i]); };
    size_t b = 0;
    while (!eligible(b)) ++b;
    for (size_t i = b + 1; i < cs.size(); ++i)
      if (eligible(i) && cs[i].score < cs[b].score) b = i;
    const double limit = cs[b].score * (1.0 + cfg.symmetry_tolerance);
    size_t s = b;
    for (size_t i = 0; i < cs.size(); ++i)
      if (eligible(i) && cs[i].score <= limit && angle(cs[i].t) < angle(cs[s].t) - 1e-6) s = i;
    return s;
  };

  // Fine pass on the best few (and the coarse pick) with the inlier distance
  // as correspondence gate: with a wide gate, points missing from a partial
  // view pull the solution off by a few centimetres and degrees, enough to
  // rank a wrong symmetric pose first.
  // (Measured and not kept, docs/bench/end-to-end.md 2026-11-27: the three
  // best *distinct* poses, or extra fine passes for distinct coarse ties:
  // neither listed a true pose more often among the alternatives.)
  std::vector<size_t> chosen;
  for (size_t i = 0; i < std::min<size_t>(coarse.size(), 3); ++i) chosen.push_back(i);
  const size_t coarse_pick = pick(coarse);
  if (coarse_pick >= chosen.size()) chosen.push_back(coarse_pick);
  // The least turned hypothesis always gets its fine pass: the simplest
  // explanation of a move, and a symmetric shape's (a box's) true pose,
  // which a coarse pass with partial views can rank below its half-turned
  // twin by more than symmetry_tolerance (measured: exp1 from an OS1-64).
  size_t least_turned = 0;
  for (size_t i = 1; i < coarse.size(); ++i)
    if (angle(coarse[i].t) < angle(coarse[least_turned].t)) least_turned = i;
  if (std::find(chosen.begin(), chosen.end(), least_turned) == chosen.end()) chosen.push_back(least_turned);
  // The best admissible hypothesis gets its fine pass too.
  for (size_t i = 0; cfg.admissible && i < coarse.size(); ++i)
    if (admissible(coarse[i])) {
      if (std::find(chosen.begin(), chosen.end(), i) == chosen.end()) chosen.push_back(i);
      break;
    }
  // GICP's plane-to-plane minimum can sit a few degrees off on box-like
  // objects (measured: a cart stuck at a 90-degree hypothesis, 4.5 deg from
  // the truth, which point-to-point ICP reached with a lower score), so a
  // point-to-point polish competes too. Never worse than the coarse result.
  const double fine_gate = std::min(cfg.max_correspondence, cfg.inlier_distance);
  use_fine_points();
  std::vector<Candidate> fine;
  for (size_t i : chosen) {
    Candidate best_i = coarse[i];
    auto consider = [&](const Eigen::Isometry3d& t) {
      Candidate c{t, 0.0, 0.0, 0.0};
      c.score = score_of(c.t, c.in_source, c.in_target);
      if (c.score < best_i.score) best_i = c;
    };
    // A coarse pose from a thinned source sits wherever the thin points
    // let it slide along a large face: first the wide gate again on the
    // fine points, then the narrow one.
    if (!fine_is_coarse) consider(refine(coarse[i].t, cfg.max_correspondence));
    consider(refine(best_i.t, fine_gate));
    if (use_gicp) consider(refine(best_i.t, fine_gate, true));
    fine.push_back(best_i);
  }
  const size_t win = pick(fine);
  const bool turned_away = cfg.admissible && pick(fine, false) != win;
  const Candidate& winner = fine[win];
  IcpResult best;
  best.hypotheses = static_cast<int>(guesses.size());
  best.score = winner.score;
  best.transform = winner.t;
  best.source_inliers = winner.in_source;
  best.target_inliers = winner.in_target;
  best.inlier_ratio = 0.5 * (winner.in_source + winner.in_target);
  best.inadmissible_preferred = turned_away;
  // A tie A = S * T reveals a symmetry S = A * T^-1 of the target (a
  // square crate's quarter turn); its powers S^k * T are tried too (the
  // crate's half turn), scored as they stand: the fine pass refines a few
  // poses only and may have missed them.
  if (!cfg.list_alternatives) return best;
  std::vector<Candidate> ties = fine;
  for (const Eigen::Isometry3d& a : distinct_ties(fine, win, cs, cfg)) {
    const Eigen::Isometry3d symmetry = a * winner.t.inverse();
    Eigen::Isometry3d p = symmetry * a;
    for (int k = 2; k < kMaxSymmetryPower && distinct_poses(p, winner.t, cs, cfg); ++k, p = symmetry * p) {
      Candidate c{p, 0.0, 0.0, 0.0};
      c.score = score_of(c.t, c.in_source, c.in_target);
      ties.push_back(c);
    }
  }
  best.alternatives = distinct_ties(ties, win, cs, cfg);
  if (cfg.admissible)
    best.alternatives.erase(std::remove_if(best.alternatives.begin(), best.alternatives.end(),
                                           [&](const Eigen::Isometry3d& a) { return !cfg.admissible(a); }),
                            best.alternatives.end());
  return best;
}

}  // namespace

IcpResult icp_refine(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                     const IcpConfig& cfg) {
  if (source.empty() || target.empty()) throw Error("cannot register an object with no points");
  const Cloud::Ptr src = voxel_cloud(source, cfg.voxel), dst = voxel_cloud(target, cfg.voxel);
  // ICP pulls every source point towards the target, so a source with parts
  // the target never saw is dragged off. Register the view covering fewer
  // voxels (mostly the partial one) onto the other, then invert.
  if (dst->size() >= src->size()) return refine_pair(source, target, src, dst, cfg);
  IcpConfig reversed = cfg;
  reversed.floor_lift = -cfg.floor_lift;
  if (cfg.admissible)
    reversed.admissible = [&cfg](const Eigen::Isometry3d& t) { return cfg.admissible(t.inverse()); };
  IcpResult r = refine_pair(target, source, dst, src, reversed);
  r.transform = r.transform.inverse();
  for (Eigen::Isometry3d& a : r.alternatives) a = a.inverse();
  std::swap(r.source_inliers, r.target_inliers);
  return r;
}

}  // namespace lista::registration
