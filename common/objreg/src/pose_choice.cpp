#include "pose_choice.hpp"

#include <algorithm>
#include <cmath>

namespace lista::objreg {

double turn_of(const Eigen::Isometry3d& t) { return Eigen::AngleAxisd(t.linear()).angle(); }

size_t simplest_best(const std::vector<Candidate>& cs, const IcpConfig& cfg, bool constrained) {
  auto admissible = [&](const Candidate& c) { return !cfg.admissible || cfg.admissible(c.t); };
  const bool any = constrained && std::any_of(cs.begin(), cs.end(), admissible);
  auto eligible = [&](size_t i) { return !any || admissible(cs[i]); };
  size_t b = 0;
  while (!eligible(b)) ++b;
  for (size_t i = b + 1; i < cs.size(); ++i)
    if (eligible(i) && cs[i].score < cs[b].score) b = i;
  const double limit = cs[b].score * (1.0 + cfg.symmetry_tolerance);
  size_t s = b;
  for (size_t i = 0; i < cs.size(); ++i)
    if (eligible(i) && cs[i].score <= limit && turn_of(cs[i].t) < turn_of(cs[s].t) - 1e-6) s = i;
  return s;
}

bool distinct_poses(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, const Eigen::Vector3d& c,
                    const IcpConfig& cfg) {
  const double degrees = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
  return degrees >= cfg.distinct_degrees || (a * c - b * c).norm() >= cfg.distinct_metres;
}

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

}  // namespace lista::objreg
