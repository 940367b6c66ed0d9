#include "global_search.hpp"

#include <lista/parallel.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lista::align {

namespace {

// A mission's map from above: the points of its keyframe submaps inside the
// height band over each keyframe's ground, in the mission's map frame, and
// the ground's height there.
struct PlanView {
  std::vector<Eigen::Vector2d> points;
  double ground = 0.0;  // m: median of the keyframes' ground heights
};

PlanView plan_view(const std::vector<Keyframe>& keyframes, size_t mission, const GlobalSearchOptions& o) {
  PlanView view;
  std::vector<double> grounds;
  for (const Keyframe& k : keyframes) {
    if (k.mission != mission || k.submap.empty()) continue;
    std::vector<float> z;
    z.reserve(k.submap.size());
    for (const auto& p : k.submap) z.push_back(p.z());
    // The 5th percentile: the ground under the sensor, not a stray low point.
    const double ground = geometry::kth_smallest(z, z.size() / 20);
    grounds.push_back((k.frame * Eigen::Vector3d(0, 0, ground)).z());
    for (const auto& p : k.submap)
      if (p.z() >= ground + o.band_low && p.z() <= ground + o.band_high)
        view.points.push_back((k.frame * p.cast<double>()).head<2>());
  }
  if (!grounds.empty()) view.ground = geometry::median(grounds);
  return view;
}

using CellList = std::vector<Eigen::Vector2i>;

// Distinct cells of `points` turned by `yaw` about the map origin.
CellList cells_of(const std::vector<Eigen::Vector2d>& points, double yaw, double cell) {
  const Eigen::Rotation2Dd turn(yaw);
  std::vector<uint64_t> keys;
  keys.reserve(points.size());
  for (const auto& p : points) {
    const Eigen::Vector2d q = turn * p / cell;
    keys.push_back((uint64_t(uint32_t(int32_t(std::floor(q.x())))) << 32) | uint32_t(int32_t(std::floor(q.y()))));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  CellList out;
  out.reserve(keys.size());
  for (uint64_t k : keys) out.emplace_back(int32_t(uint32_t(k >> 32)), int32_t(uint32_t(k)));
  return out;
}

// Occupied cells of the reference map, grown by `grow` cells so that a query
// cell within that many of an occupied one counts.
class PlanGrid {
 public:
  PlanGrid() = default;
  PlanGrid(const std::vector<Eigen::Vector2d>& points, double cell, int grow) {
    const CellList cells = cells_of(points, 0.0, cell);
    if (cells.empty()) return;
    Eigen::Vector2i lo = cells.front(), hi = cells.front();
    for (const auto& c : cells) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    lo_ = lo.array() - grow;
    size_ = (hi - lo).array() + 2 * grow + 1;
    occupied_.assign(size_t(size_.x()) * size_t(size_.y()), 0);
    for (const auto& c : cells)
      for (int dy = -grow; dy <= grow; ++dy)
        for (int dx = -grow; dx <= grow; ++dx) occupied_[index(c.x() + dx, c.y() + dy)] = 1;
  }
  bool at(int x, int y) const {
    x -= lo_.x();
    y -= lo_.y();
    return unsigned(x) < unsigned(size_.x()) && unsigned(y) < unsigned(size_.y()) &&
           occupied_[size_t(y) * size_t(size_.x()) + size_t(x)];
  }
  // The occupied cells, row by row.
  CellList occupied() const {
    CellList out;
    for (int y = 0; y < size_.y(); ++y)
      for (int x = 0; x < size_.x(); ++x)
        if (occupied_[size_t(y) * size_t(size_.x()) + size_t(x)]) out.emplace_back(lo_.x() + x, lo_.y() + y);
    return out;
  }
  Eigen::Vector2i lo() const { return lo_; }
  Eigen::Vector2i hi() const { return lo_ + size_ - Eigen::Vector2i::Ones(); }
  bool empty() const { return occupied_.empty(); }

 private:
  size_t index(int x, int y) const { return size_t(y - lo_.y()) * size_t(size_.x()) + size_t(x - lo_.x()); }
  Eigen::Vector2i lo_ = Eigen::Vector2i::Zero(), size_ = Eigen::Vector2i::Zero();
  std::vector<uint8_t> occupied_;
};

// Share of `cells`, shifted by `shift`, on occupied reference cells.
double score(const PlanGrid& grid, const CellList& cells, const Eigen::Vector2i& shift) {
  size_t hits = 0;
  for (const auto& c : cells) hits += grid.at(c.x() + shift.x(), c.y() + shift.y());
  return cells.empty() ? 0.0 : double(hits) / double(cells.size());
}

// Share of the query's plan-view cells that `reference_T_query` puts within
// one cell of an occupied reference cell (`grid` grown by one).
double plan_agreement(const PlanGrid& grid, const std::vector<Eigen::Vector2d>& query,
                      const Eigen::Isometry3d& reference_T_query, double cell) {
  const double yaw = std::atan2(reference_T_query.linear()(1, 0), reference_T_query.linear()(0, 0));
  const Eigen::Vector2d shift = reference_T_query.translation().head<2>();
  std::vector<Eigen::Vector2d> moved;
  moved.reserve(query.size());
  const Eigen::Rotation2Dd turn(yaw);
  for (const auto& p : query) moved.push_back(turn * p + shift);
  return score(grid, cells_of(moved, 0.0, cell), Eigen::Vector2i::Zero());
}

struct Hypothesis {
  double yaw = 0.0;
  Eigen::Vector2d shift = Eigen::Vector2d::Zero();  // m
  double score = 0.0;
};

double angle_between(double a, double b) { return std::abs(std::remainder(a - b, 2.0 * M_PI)); }

// Every shift of `cells` that puts its bounding box on the grid's, scored;
// the best and the best clearly apart from it.
// `occupied`: the grid's occupied cells (PlanGrid::occupied), listed once
// for every yaw.
std::vector<Hypothesis> best_shifts(const PlanGrid& grid, const CellList& occupied, const CellList& cells, double yaw,
                                    double cell) {
  if (cells.empty() || grid.empty()) return {};
  Eigen::Vector2i lo = cells.front(), hi = cells.front();
  for (const auto& c : cells) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
  struct Scored {
    Eigen::Vector2i shift;
    double score;
  };
  // Each query cell on each occupied cell votes for the shift that puts it
  // there: the hits of every shift at once, in fewer steps than scoring
  // shift by shift (occupied cells are fewer than shifts).
  const Eigen::Vector2i first = grid.lo() - hi, last = grid.hi() - lo;
  const size_t width = size_t(last.x() - first.x() + 1);
  std::vector<uint32_t> hits(width * size_t(last.y() - first.y() + 1), 0);
  for (const auto& g : occupied)
    for (const auto& c : cells) ++hits[size_t(g.y() - c.y() - first.y()) * width + size_t(g.x() - c.x() - first.x())];
  std::vector<Scored> all;
  all.reserve(hits.size());
  for (int y = first.y(); y <= last.y(); ++y)
    for (int x = first.x(); x <= last.x(); ++x)
      all.push_back({{x, y}, double(hits[size_t(y - first.y()) * width + size_t(x - first.x())]) / double(cells.size())});
  std::vector<Hypothesis> out;
  for (int pick = 0; pick < 2 && !all.empty(); ++pick) {
    const auto best = std::max_element(all.begin(), all.end(), [](const Scored& a, const Scored& b) {
      return a.score < b.score;
    });
    const Eigen::Vector2i at = best->shift;
    out.push_back({yaw, at.cast<double>() * cell, best->score});
    all.erase(std::remove_if(all.begin(), all.end(),
                             [&](const Scored& s) { return (s.shift - at).cwiseAbs().maxCoeff() <= 3; }),
              all.end());
  }
  return out;
}

}  // namespace

// A mission's plan view, its fine grid (grown by one cell, for scoring a
// query on it) and its whole map prepared for registration.
struct MissionMaps::Maps {
  PlanView view;
  PlanGrid fine_grid;
  PreparedCloud prepared;
  size_t map_points = 0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // the map's centroid
};

namespace {

std::vector<GlobalPlacement> placements_of(const MissionMaps::Maps& reference, const MissionMaps::Maps& query,
                                           const GlobalSearchOptions& o, int threads) {
  const PlanView& ref = reference.view;
  const PlanView& qry = query.view;
  if (ref.points.empty() || qry.points.empty()) return {};
  // Coarse cells: no finer than a map's extent over max_coarse_cells, which
  // bounds the work on a large site.
  double extent = 0.0;
  for (const PlanView* v : {&ref, &qry}) {
    Eigen::Vector2d lo = v->points.front(), hi = lo;
    for (const auto& p : v->points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    extent = std::max(extent, (hi - lo).maxCoeff());
  }
  const double coarse = std::max(o.coarse_cell, extent / std::max(1, o.max_coarse_cells));
  const PlanGrid coarse_grid(ref.points, coarse, 0);
  const CellList occupied = coarse_grid.occupied();
  const int yaws = std::max(1, int(std::lround(2.0 * M_PI / o.yaw_step)));
  std::vector<std::vector<Hypothesis>> per_yaw(size_t(yaws), std::vector<Hypothesis>{});
  parallel_for(size_t(yaws), threads, [&](size_t i) {
    const double yaw = 2.0 * M_PI * double(i) / double(yaws);
    per_yaw[i] = best_shifts(coarse_grid, occupied, cells_of(qry.points, yaw, coarse), yaw, coarse);
  });
  std::vector<Hypothesis> all;
  for (const auto& list : per_yaw) all.insert(all.end(), list.begin(), list.end());
  std::stable_sort(all.begin(), all.end(), [](const Hypothesis& a, const Hypothesis& b) { return a.score > b.score; });
  // Distinct placements only: a good fit's neighbours in yaw and shift score
  // nearly as well and would crowd out the alternatives.
  std::vector<Hypothesis> kept;
  for (const auto& h : all) {
    if (int(kept.size()) >= o.hypotheses) break;
    const bool near = std::any_of(kept.begin(), kept.end(), [&](const Hypothesis& k) {
      return angle_between(k.yaw, h.yaw) < 3.5 * o.yaw_step && (k.shift - h.shift).norm() < 3.0 * coarse;
    });
    if (!near) kept.push_back(h);
  }
  // Fine search around each: yaw in half-degree steps, shifts in fine cells,
  // a query cell counted when within one cell of the reference's.
  const PlanGrid& fine_grid = reference.fine_grid;
  const double yaw_fine = 0.5 * M_PI / 180.0;
  const int yaw_span = int(std::ceil(o.yaw_step / yaw_fine));
  const int reach = int(std::ceil((coarse + o.cell) / o.cell));
  std::vector<GlobalPlacement> out(kept.size());
  parallel_for(kept.size(), threads, [&](size_t i) {
    Hypothesis best = kept[i];
    best.score = -1.0;
    const Eigen::Vector2i centre = (kept[i].shift / o.cell).array().round().cast<int>();
    for (int a = -yaw_span; a <= yaw_span; ++a) {
      const double yaw = kept[i].yaw + a * yaw_fine;
      const CellList cells = cells_of(qry.points, yaw, o.cell);
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const Eigen::Vector2i shift = centre + Eigen::Vector2i(dx, dy);
          const double s = score(fine_grid, cells, shift);
          if (s > best.score) best = {yaw, shift.cast<double>() * o.cell, s};
        }
    }
    GlobalPlacement& p = out[i];
    p.reference_T_query.linear() = Eigen::AngleAxisd(best.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.reference_T_query.translation() = Eigen::Vector3d(best.shift.x(), best.shift.y(), ref.ground - qry.ground);
    p.plan_score = best.score;
  });
  std::stable_sort(out.begin(), out.end(),
                   [](const GlobalPlacement& a, const GlobalPlacement& b) { return a.plan_score > b.plan_score; });
  return out;
}

// A mission's keyframe submaps joined in its map frame, downsampled again
// where neighbouring submaps overlap.
Cloud mission_map(const std::vector<Keyframe>& keyframes, size_t mission, double voxel) {
  Cloud joined;
  for (const Keyframe& k : keyframes)
    if (k.mission == mission)
      for (const auto& p : k.submap) joined.push_back((k.frame * p.cast<double>()).cast<float>());
  return voxel_downsample(joined, voxel);
}

Eigen::Vector3d centroid(const Cloud& cloud) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : cloud) sum += p.cast<double>();
  return cloud.empty() ? sum : Eigen::Vector3d(sum / double(cloud.size()));
}

}  // namespace

MissionMaps::MissionMaps(const std::vector<Keyframe>& keyframes, const GlobalSearchOptions& options,
                         const VerifyOptions& verify)
    : keyframes_(keyframes), options_(options), registration_(verify.registration) {
  // The maps may cover different extents (a short mission on a long one),
  // so the overlap that counts is the smaller map's, and the registration's
  // early refusal, which asks for overlap both ways, is off.
  registration_.min_coarse_overlap = 0.0;
}

MissionMaps::~MissionMaps() = default;

const MissionMaps::Maps& MissionMaps::of(size_t mission) {
  auto& made = made_[mission];
  if (!made) {
    auto maps = std::make_unique<Maps>();
    maps->view = plan_view(keyframes_, mission, options_);
    maps->fine_grid = PlanGrid(maps->view.points, options_.cell, 1);
    const Cloud map = mission_map(keyframes_, mission, registration_.voxel);
    maps->map_points = map.size();
    maps->centre = centroid(map);
    maps->prepared = PreparedCloud(map, registration_);
    made = std::move(maps);
  }
  return *made;
}

std::vector<GlobalPlacement> plan_view_placements(MissionMaps& maps, size_t reference, size_t query, int threads) {
  return placements_of(maps.of(reference), maps.of(query), maps.options(), threads);
}

std::vector<GlobalPlacement> plan_view_placements(const std::vector<Keyframe>& keyframes, size_t reference,
                                                  size_t query, const GlobalSearchOptions& o, int threads) {
  MissionMaps maps(keyframes, o, VerifyOptions{});
  return plan_view_placements(maps, reference, query, threads);
}

PlacementSearch verified_placements(MissionMaps& maps, size_t reference, size_t query,
                                    std::vector<GlobalPlacement> placements, int threads,
                                    const std::optional<Eigen::Isometry3d>& incumbent) {
  PlacementSearch out;
  if (placements.empty()) return out;
  const GlobalSearchOptions& o = maps.options();
  const MissionMaps::Maps& ref = maps.of(reference);
  const MissionMaps::Maps& qry = maps.of(query);
  double incumbent_plan_score = 0.0;
  // The incumbent competes as one more placement, registered the same way.
  if (incumbent) {
    GlobalPlacement p;
    p.reference_T_query = *incumbent;
    placements.push_back(p);
    incumbent_plan_score = plan_agreement(ref.fine_grid, qry.view.points, *incumbent, o.cell);
  }
  // Whole map onto whole map: missions of a few scans share no two keyframes
  // close enough for their submaps to overlap, while their maps do.
  out.query_centre = qry.centre;
  const bool query_smaller = qry.map_points <= ref.map_points;
  std::vector<std::optional<GlobalPlacement>> verified(placements.size());
  parallel_for(placements.size(), threads, [&](size_t i) {
    const RegistrationResult r =
        register_prepared(qry.prepared, ref.prepared, placements[i].reference_T_query, maps.registration());
    const double overlap = query_smaller ? r.overlap : r.reverse_overlap;
    if (!r.converged || r.inlier_rmse > o.max_rmse) return;
    GlobalPlacement p = placements[i];
    p.reference_T_query = r.transform;
    p.plan_score = plan_agreement(ref.fine_grid, qry.view.points, r.transform, o.cell);
    p.overlap = overlap;
    p.rmse = r.inlier_rmse;
    p.incumbent = incumbent && i + 1 == placements.size();
    p.incumbent_plan_score = incumbent_plan_score;
    verified[i] = std::move(p);
  });
  for (auto& p : verified)
    if (p) out.verified.push_back(std::move(*p));
  return out;
}

PlacementSearch verified_placements(const std::vector<Keyframe>& keyframes, size_t reference, size_t query,
                                    const GlobalSearchOptions& o, const VerifyOptions& verify, int threads,
                                    const std::optional<Eigen::Isometry3d>& incumbent) {
  MissionMaps maps(keyframes, o, verify);
  return verified_placements(maps, reference, query, plan_view_placements(maps, reference, query, threads), threads,
                             incumbent);
}

bool same_placement(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, const Eigen::Vector3d& centre) {
  return (a * centre - b * centre).norm() <= 1.0 && rotation_angle(a.linear().transpose() * b.linear()) <= 5.0 * M_PI / 180.0;
}

std::vector<Closure> placement_closures(const std::vector<Keyframe>& keyframes, size_t reference, size_t query,
                                        const GlobalPlacement& placement, int max_pairs) {
  // Each query keyframe (at most max_pairs, spread along the mission) with
  // the reference keyframe nearest to where it lands.
  std::vector<size_t> refs, queries;
  for (size_t i = 0; i < keyframes.size(); ++i) {
    if (keyframes[i].mission == reference) refs.push_back(i);
    if (keyframes[i].mission == query) queries.push_back(i);
  }
  std::vector<Closure> out;
  if (refs.empty() || queries.empty()) return out;
  const size_t pairs = max_pairs > 0 ? std::min(queries.size(), size_t(max_pairs)) : queries.size();
  for (size_t j = 0; j < pairs; ++j) {
    const size_t q = queries[j * queries.size() / pairs];
    const Eigen::Isometry3d at = placement.reference_T_query * keyframes[q].frame;
    size_t nearest = refs.front();
    for (size_t r : refs)
      if ((keyframes[r].frame.translation() - at.translation()).norm() <
          (keyframes[nearest].frame.translation() - at.translation()).norm())
        nearest = r;
    out.push_back(Closure{nearest, q, keyframes[nearest].frame.inverse() * at, placement.overlap, placement.rmse, 1.0});
  }
  return out;
}

std::optional<GlobalPlacement> plan_view_choice(const PlacementSearch& search, const GlobalSearchOptions& o,
                                                const std::optional<Eigen::Isometry3d>& incumbent) {
  // Ranked by the plan view, not the overlap: the overlap counts floor,
  // ceiling and walls, which a half-turned symmetric room fits as well,
  // while the plan view leaves out floor and ceiling, so what stands in the
  // room weighs more (a 14 x 10 m office of 2 scans a mission: overlap 0.83
  // against 0.78 turned, plan view before registration 0.91 against 0.78).
  std::optional<GlobalPlacement> best;
  for (const auto& p : search.verified)
    if (p.overlap >= o.min_overlap && (!best || p.plan_score > best->plan_score)) best = p;
  if (!best) return std::nullopt;
  auto distinct = [&](const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return !same_placement(a, b, search.query_centre);
  };
  // The incumbent's own fit, or one that agrees with it: nothing new.
  if (incumbent && (best->incumbent || !distinct(best->reference_T_query, *incumbent))) return std::nullopt;
  // As the closures put it, before any registration: a placement the
  // whole-map registration merely polishes (a closure a metre off on a
  // drifting map) is no reason to overrule them.
  if (incumbent && best->plan_score < (1.0 + o.margin) * best->incumbent_plan_score) return std::nullopt;
  // A rectangular hall fits its own map turned by half a turn nearly as
  // well; only the furniture tells. A placement no better than a distinct
  // rival is a guess, and a wrong placement costs more than an error.
  for (const auto& p : search.verified)
    if (distinct(p.reference_T_query, best->reference_T_query) && best->plan_score < (1.0 + o.margin) * p.plan_score)
      return std::nullopt;
  return best;
}

std::optional<GlobalPlacement> global_search(const std::vector<Keyframe>& keyframes, size_t reference, size_t query,
                                             const GlobalSearchOptions& o, const VerifyOptions& verify, int threads,
                                             const std::optional<Eigen::Isometry3d>& incumbent) {
  auto best = plan_view_choice(verified_placements(keyframes, reference, query, o, verify, threads, incumbent), o,
                               incumbent);
  // The placement as closures between keyframes, so that the pose graph
  // holds it like any other.
  if (best) best->closures = placement_closures(keyframes, reference, query, *best, o.max_pairs);
  return best;
}

}  // namespace lista::align
