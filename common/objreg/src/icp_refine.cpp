// Object-pair ICP (PCL); used by register.icp and match.weighted. The
// method is described in icp_refine.hpp; its parts: where ICP starts
// (hypotheses.hpp), ICP and scoring on one pair (pair_icp.hpp), which pose
// wins and which tie (pose_choice.hpp).
#include <lista_objreg/icp_refine.hpp>

#include "hypotheses.hpp"
#include "pair_icp.hpp"
#include "pose_choice.hpp"
#include "voxel_cloud.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace lista::objreg {

namespace {

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

// Coarse pass from every start with the wide correspondence distance, best
// first. Corner starts only where no centroid start explained the moved
// view (the one covering fewer voxels) in a pose the caller accepts: they
// cost as much again. One candidate per start registered.
std::vector<Candidate> coarse_pass(PairIcp& pair, const std::vector<Eigen::Vector3f>& source,
                                   const std::vector<Eigen::Vector3f>& target, const Eigen::Vector3d& cs,
                                   const Eigen::Vector3d& ct, const IcpConfig& cfg,
                                   const std::vector<Eigen::Isometry3d>& starts) {
  std::vector<Candidate> coarse;
  auto coarse_from = [&](const Eigen::Isometry3d& guess) {
    coarse.push_back(pair.scored(pair.refine(guess, cfg.max_correspondence)));
  };
  for (const Eigen::Isometry3d& guess : starts) coarse_from(guess);
  const bool explained = std::any_of(coarse.begin(), coarse.end(), [&](const Candidate& c) {
    return c.in_source >= kExplainedShare && (!cfg.admissible || cfg.admissible(c.t));
  });
  if (cfg.corner_hypotheses && !explained) {
    const double lift = std::isfinite(cfg.floor_lift) ? cfg.floor_lift : ct.z() - cs.z();
    std::vector<std::pair<double, Eigen::Isometry3d>> corners;
    for (const Eigen::Isometry3d& g : corner_starts(source, target, lift, kCornerSlack))
      corners.emplace_back(pair.scored(g).score, g);
    std::stable_sort(corners.begin(), corners.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    if (corners.size() > kCornerStartsRegistered) corners.resize(kCornerStartsRegistered);
    for (const auto& start : corners) coarse_from(start.second);
  }
  std::stable_sort(coarse.begin(), coarse.end(), [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
  return coarse;
}

// The coarse poses that get a fine pass: the best three and the coarse pick
// (measured and not kept, docs/bench/end-to-end.md 2026-11-27: the three
// best *distinct* poses, or extra fine passes for distinct coarse ties:
// neither listed a true pose more often among the alternatives). The least
// turned always: the simplest explanation of a move, and a symmetric
// shape's (a box's) true pose, which a coarse pass with partial views can
// rank below its half-turned twin by more than symmetry_tolerance
// (measured: exp1 from an OS1-64). And the best admissible one.
std::vector<size_t> fine_pass_choices(const std::vector<Candidate>& coarse, const IcpConfig& cfg) {
  std::vector<size_t> chosen;
  for (size_t i = 0; i < std::min<size_t>(coarse.size(), 3); ++i) chosen.push_back(i);
  const size_t coarse_pick = simplest_best(coarse, cfg);
  if (coarse_pick >= chosen.size()) chosen.push_back(coarse_pick);
  size_t least_turned = 0;
  for (size_t i = 1; i < coarse.size(); ++i)
    if (turn_of(coarse[i].t) < turn_of(coarse[least_turned].t)) least_turned = i;
  if (std::find(chosen.begin(), chosen.end(), least_turned) == chosen.end()) chosen.push_back(least_turned);
  for (size_t i = 0; cfg.admissible && i < coarse.size(); ++i)
    if (cfg.admissible(coarse[i].t)) {
      if (std::find(chosen.begin(), chosen.end(), i) == chosen.end()) chosen.push_back(i);
      break;
    }
  return chosen;
}

// Fine pass with the inlier distance as correspondence gate: with a wide
// gate, points missing from a partial view pull the solution off by a few
// centimetres and degrees, enough to rank a wrong symmetric pose first.
// GICP's plane-to-plane minimum can sit a few degrees off on box-like
// objects (measured: a cart stuck at a 90-degree hypothesis, 4.5 deg from
// the truth, which point-to-point ICP reached with a lower score), so a
// point-to-point polish competes too. Never worse than the coarse result.
std::vector<Candidate> fine_pass(PairIcp& pair, const std::vector<Candidate>& coarse,
                                 const std::vector<size_t>& chosen, const IcpConfig& cfg) {
  const double fine_gate = std::min(cfg.max_correspondence, cfg.inlier_distance);
  pair.use_fine_points();
  std::vector<Candidate> fine;
  for (size_t i : chosen) {
    Candidate best_i = coarse[i];
    auto consider = [&](const Eigen::Isometry3d& t) {
      const Candidate c = pair.scored(t);
      if (c.score < best_i.score) best_i = c;
    };
    // A coarse pose from a thinned source sits wherever the thin points
    // let it slide along a large face: first the wide gate again on the
    // fine points, then the narrow one.
    if (!pair.fine_is_coarse()) consider(pair.refine(coarse[i].t, cfg.max_correspondence));
    consider(pair.refine(best_i.t, fine_gate));
    if (pair.uses_gicp()) consider(pair.refine(best_i.t, fine_gate, true));
    fine.push_back(best_i);
  }
  return fine;
}

// The poses tying with fine[win]. A tie A = S * T reveals a symmetry
// S = A * T^-1 of the target (a square crate's quarter turn); its powers
// S^k * T are tried too (the crate's half turn), scored as they stand: the
// fine pass refines a few poses only and may have missed them.
std::vector<Eigen::Isometry3d> alternatives(const PairIcp& pair, const std::vector<Candidate>& fine, size_t win,
                                            const Eigen::Vector3d& cs, const IcpConfig& cfg) {
  const Candidate& winner = fine[win];
  std::vector<Candidate> ties = fine;
  for (const Eigen::Isometry3d& a : distinct_ties(fine, win, cs, cfg)) {
    const Eigen::Isometry3d symmetry = a * winner.t.inverse();
    Eigen::Isometry3d p = symmetry * a;
    for (int k = 2; k < kMaxSymmetryPower && distinct_poses(p, winner.t, cs, cfg); ++k, p = symmetry * p)
      ties.push_back(pair.scored(p));
  }
  std::vector<Eigen::Isometry3d> out = distinct_ties(ties, win, cs, cfg);
  if (cfg.admissible)
    out.erase(std::remove_if(out.begin(), out.end(), [&](const Eigen::Isometry3d& a) { return !cfg.admissible(a); }),
              out.end());
  return out;
}

// Registers `source` onto `target` (their voxelised clouds `src`, `dst`).
IcpResult refine_pair(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                      const Cloud::Ptr& src, const Cloud::Ptr& dst, const IcpConfig& cfg) {
  PairIcp pair(src, dst, cfg);
  const PrincipalFrame fs = principal_frame(source), ft = principal_frame(target);
  const Eigen::Vector3d cs = fs.frame.translation(), ct = ft.frame.translation();
  const std::vector<Eigen::Isometry3d> starts = centroid_starts(fs, ft, cfg);
  const std::vector<Candidate> coarse = coarse_pass(pair, source, target, cs, ct, cfg, starts);
  const std::vector<Candidate> fine = fine_pass(pair, coarse, fine_pass_choices(coarse, cfg), cfg);
  const size_t win = simplest_best(fine, cfg);
  const Candidate& winner = fine[win];
  IcpResult best;
  best.hypotheses = static_cast<int>(coarse.size());  // every start registered
  best.score = winner.score;
  best.transform = winner.t;
  best.source_inliers = winner.in_source;
  best.target_inliers = winner.in_target;
  best.inlier_ratio = 0.5 * (winner.in_source + winner.in_target);
  best.inadmissible_preferred = cfg.admissible && simplest_best(fine, cfg, false) != win;
  if (cfg.list_alternatives) best.alternatives = alternatives(pair, fine, win, cs, cfg);
  return best;
}

}  // namespace

IcpConfig shape_check_config(double voxel, double inlier_distance) {
  IcpConfig c;
  c.method = PairMethod::icp;
  c.voxel = voxel;
  c.inlier_distance = inlier_distance;
  // Wide enough for the coarse pass to pull a partial view (whose centroid
  // is off the whole object's by a fraction of its size) into place.
  c.max_correspondence = std::max(0.3, 3.0 * inlier_distance);
  c.max_iterations = 30;
  c.max_points = 400;
  c.fine_max_points = -1;  // as max_points: a check on every candidate pair stays cheap
  c.max_score_points = 2000;
  c.svd_flips = false;          // objects stand on floors: the yaw turns suffice
  c.list_alternatives = false;  // a check needs the fit, not the other poses (scoring them cost ~10 %)
  return c;
}

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

}  // namespace lista::objreg
