#include "seen_through.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>

namespace lista::align {
namespace {

// The bin of direction p (azimuth columns, elevation rows); false at the origin.
bool bin_of(const Eigen::Vector3d& p, int columns, int rows, int& column, int& row) {
  const double r = p.norm();
  if (r < 1e-6) return false;
  column = std::min(columns - 1, int((std::atan2(p.y(), p.x()) + M_PI) / (2.0 * M_PI) * columns));
  row = std::min(rows - 1, int((std::asin(std::clamp(p.z() / r, -1.0, 1.0)) + M_PI / 2.0) / M_PI * rows));
  return true;
}

}  // namespace

SeenThrough::SeenThrough(const Cloud& points)
    : nearest_(size_t(kColumns) * kRows, std::numeric_limits<float>::infinity()) {
  for (const auto& p : points) {
    int column = 0, row = 0;
    const Eigen::Vector3d q = p.cast<double>();
    if (!bin_of(q, kColumns, kRows, column, row)) continue;
    float& nearest = nearest_[size_t(row) * kColumns + size_t(column)];
    nearest = std::min(nearest, float(q.norm()));
  }
}

double SeenThrough::share_in_front(const Cloud& points, const Eigen::Isometry3d& sensor_T_points) const {
  size_t known = 0, in_front = 0;
  const size_t stride = std::max<size_t>(1, points.size() / kMaxPoints);
  for (size_t i = 0; i < points.size(); i += stride) {
    const Eigen::Vector3d q = sensor_T_points * points[i].cast<double>();
    int column = 0, row = 0;
    if (!bin_of(q, kColumns, kRows, column, row)) continue;
    // The nearest return about the direction: a point at a depth edge is
    // not taken for one in front of the background beside it.
    float nearest = std::numeric_limits<float>::infinity();
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int r = row + dr, c = (column + dc + kColumns) % kColumns;
        if (r >= 0 && r < kRows) nearest = std::min(nearest, nearest_[size_t(r) * kColumns + size_t(c)]);
      }
    if (!std::isfinite(nearest)) continue;
    ++known;
    if (q.norm() < nearest - std::max(0.5, 0.05 * double(nearest))) ++in_front;
  }
  return known ? double(in_front) / double(known) : 0.0;
}

double conflicts_between(const std::vector<Keyframe>& kf, const std::vector<size_t>& keyframes,
                         const std::vector<SeenThrough>& seen, size_t a, size_t b, const Eigen::Isometry3d& a_T_b,
                         size_t& shares) {
  double sum = 0.0;
  for (size_t i = 0; i < keyframes.size(); ++i)
    for (size_t j = 0; j < keyframes.size(); ++j) {
      const Keyframe &x = kf[keyframes[i]], &y = kf[keyframes[j]];
      const bool forward = x.mission == a && y.mission == b, backward = x.mission == b && y.mission == a;
      if (!forward && !backward) continue;
      sum += seen[i].share_in_front(y.submap, x.frame.inverse() * (forward ? a_T_b : a_T_b.inverse()) * y.frame);
      ++shares;
    }
  return sum;
}

PairConflicts::PairConflicts(const std::vector<Keyframe>& kf, size_t a, size_t b) : kf_(kf), a_(a), b_(b) {
  for (size_t k = 0; k < kf.size(); ++k)
    if (kf[k].mission == a || kf[k].mission == b) keyframes_.push_back(k), seen_.emplace_back(kf[k].submap);
}

double PairConflicts::of(const Eigen::Isometry3d& a_T_b) const {
  size_t shares = 0;
  const double sum = conflicts_between(kf_, keyframes_, seen_, a_, b_, a_T_b, shares);
  return shares ? sum / double(shares) : 0.0;
}

StationJudgement judge_station_placements(const std::vector<Keyframe>& kf, size_t a, size_t b,
                                          const PlacementSearch& search, const GlobalSearchOptions& o,
                                          const std::optional<Eigen::Isometry3d>& incumbent,
                                          const std::optional<GlobalPlacement>& plan_view) {
  StationJudgement out;
  out.choice = plan_view;
  const PairConflicts judge(kf, a, b);
  std::vector<std::pair<double, const GlobalPlacement*>> scored;
  for (const auto& p : search.verified)
    if (p.overlap >= o.min_overlap) scored.emplace_back(judge.of(p.reference_T_query), &p);
  if (scored.empty()) return out;
  const auto [fewest, least] = *std::min_element(scored.begin(), scored.end(),
                                                 [](const auto& x, const auto& y) { return x.first < y.first; });
  auto agrees = [&](const GlobalPlacement* p, const Eigen::Isometry3d& t) {
    return same_placement(p->reference_T_query, t, search.query_centre);
  };
  char text[240];
  if (plan_view || incumbent) {
    // The choice is judged as verified: the closures' placement only where
    // the whole maps registered there too (a placement that puts the maps
    // apart has nothing in front of anything).
    const Eigen::Isometry3d chosen = plan_view ? plan_view->reference_T_query : *incumbent;
    std::optional<double> now;
    for (const auto& [c, p] : scored)
      if (agrees(p, chosen) && (!now || c < *now)) now = c;
    if (!now || agrees(least, chosen) || fewest >= 0.5 * *now) return out;
    out.overruled = true;
    out.choice.reset();
    if (incumbent && agrees(least, *incumbent)) {
      std::snprintf(text, sizeof text,
                    "the closures' placement kept: the plan view's best puts %.1f %% of a station's points where the "
                    "other mission's stations saw through, against %.1f %% under the closures'",
                    100.0 * *now, 100.0 * fewest);
    } else {
      out.choice = *least;
      std::snprintf(text, sizeof text,
                    "it puts %.1f %% of a station's points where the other mission's stations saw through, against "
                    "%.1f %% under the %s",
                    100.0 * fewest, 100.0 * *now, plan_view ? "plan view's best" : "closures'");
    }
    out.note = text;
    return out;
  }
  // Nothing chosen: the least conflicting placement, if it clearly is.
  double rival = INFINITY;
  for (const auto& [c, p] : scored)
    if (!agrees(p, least->reference_T_query)) rival = std::min(rival, c);
  if (!std::isfinite(rival) || fewest >= 0.5 * rival) return out;
  out.overruled = true;
  out.choice = *least;
  std::snprintf(text, sizeof text,
                "it puts %.1f %% of a station's points where the other mission's stations saw through, against %.1f "
                "%% under the best rival placement",
                100.0 * fewest, 100.0 * rival);
  out.note = text;
  return out;
}

}  // namespace lista::align
