#include <lista_raycast/misfit.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <climits>
#include <cmath>
#include <map>
#include <set>
#include <vector>

namespace lista::raycast {

namespace {
constexpr int kWindow = 2;               // voxels around a point searched for the other's surface
constexpr size_t kSamples = 8192;        // points of the mission measured for the pair's misfit
constexpr size_t kRegionSamples = 256;   // and about this many of each region's, for the region's
constexpr size_t kMinPerKind = 50;       // fewer walls (or floors) than this: that kind is not measured
constexpr double kMaxFlatness = 0.3;     // smallest / middle spread of a plane's voxels
constexpr double kFloorNormalZ = 0.7;    // |n.z| above this: a floor or a ceiling, else a wall
constexpr double kQuantisation = 0.5;    // voxels: what a point's place inside its voxel alone gives
constexpr size_t kMinPerRegionKind = 30; // a region's walls (or floors) measured from fewer are not judged

// The larger of the walls' and the floors' medians, of those with at least
// `least` measures; 0 when neither has.
double larger_median(std::vector<double>& walls, std::vector<double>& floors, size_t least) {
  double misfit = 0.0;
  for (auto* kind : {&walls, &floors})
    if (kind->size() >= least) misfit = std::max(misfit, geometry::median(*kind));
  return misfit;
}

}  // namespace

Region region_of(const Eigen::Vector3d& p, const VolumetricConfig& config, double size) {
  const double scale = config.resolution / size;
  return {int(std::floor(p.x() * scale)), int(std::floor(p.y() * scale))};
}

double region_size(const Mission& a, const Mission& b, const VolumetricConfig& config) {
  constexpr double kFinest = 2.0;    // m
  constexpr size_t kMostRegions = 256;
  std::set<Region> squares;  // of kFinest
  for (const Mission* mission : {&a, &b})
    for (size_t i = 0; i < mission->scans.size(); ++i) {
      if (!mission->scans[i].points) continue;
      const PointSet& pts = *mission->scans[i].points;
      const Eigen::Affine3d to_index = Eigen::Scaling(1.0 / config.resolution) * mission->sensor_to_common(i);
      Region last{INT_MIN, INT_MIN};
      for (size_t j = 0; j < pts.size(); j += 16) {
        const Region r = region_of(to_index * pts.xyz[j].cast<double>(), config, kFinest);
        if (r != last) squares.insert(last = r);
      }
    }
  for (int doubled = 0;; ++doubled) {
    std::set<Region> coarse;
    for (const auto& [x, y] : squares) coarse.insert({x >> doubled, y >> doubled});  // floor division by 2^doubled
    if (coarse.size() <= kMostRegions) return kFinest * double(1 << doubled);
  }
}

SurfaceMisfit surface_misfit(const Mission& mission, const OccupancyMap& other, const VolumetricConfig& config,
                             double region_size) {
  const double inv_res = 1.0 / config.resolution;
  const float occupied = logodds(config.occupied_threshold);
  auto reader = other.reader();
  size_t total = 0;
  for (const Scan& s : mission.scans) total += s.points ? s.points->size() : 0;
  const size_t step = std::max<size_t>(1, total / kSamples);
  // Each region's points are measured evenly too, however few of the
  // mission's fall in it: every kThin-th point counted first, then every
  // region_step-th of those taken (besides the pair's every step-th).
  constexpr size_t kThin = 16;
  auto each_point = [&](auto&& visit) {
    size_t k = 0;
    for (size_t i = 0; i < mission.scans.size(); ++i) {
      if (!mission.scans[i].points) continue;
      const PointSet& pts = *mission.scans[i].points;
      const Eigen::Affine3d to_index = Eigen::Scaling(inv_res) * mission.sensor_to_common(i);
      for (size_t j = 0; j < pts.size(); ++j, ++k) {
        const bool for_pair = k % step == 0;
        if (for_pair || k % kThin == 0) visit(Eigen::Vector3d(to_index * pts.xyz[j].cast<double>()), for_pair, k % kThin == 0);
      }
    }
  };
  std::map<Region, std::pair<size_t, size_t>> region_steps;  // per region: every how many-th point, points passed
  Region last{INT_MIN, INT_MIN};
  std::pair<size_t, size_t>* last_steps = nullptr;  // a scan's next point is mostly in the region of the one before
  auto steps_of = [&](const Region& region) -> std::pair<size_t, size_t>& {
    if (region != last) last = region, last_steps = &region_steps[region];
    return *last_steps;
  };
  each_point([&](const Eigen::Vector3d& p, bool, bool thinned) {
    if (thinned) ++steps_of(region_of(p, config, region_size)).first;
  });
  for (auto& [region, counts] : region_steps) counts.first = std::max<size_t>(1, counts.first / kRegionSamples);
  std::vector<double> walls, floors;
  std::map<Region, std::pair<std::vector<double>, std::vector<double>>> regions;  // their walls, floors
  std::vector<Eigen::Vector3d> held;
  each_point([&](const Eigen::Vector3d& p, bool for_pair, bool thinned) {
    const Region region = region_of(p, config, region_size);
    auto& [region_step, passed] = steps_of(region);
    const bool for_region = thinned && passed++ % region_step == 0;
    if (!for_pair && !for_region) return;
    const Voxel v = voxel_of(p);
    held.clear();
    float l;
    for (int dz = -kWindow; dz <= kWindow; ++dz)
      for (int dy = -kWindow; dy <= kWindow; ++dy)
        for (int dx = -kWindow; dx <= kWindow; ++dx) {
          const Voxel w(v.x() + dx, v.y() + dy, v.z() + dz);
          if (reader->logodds(w, l) && l > occupied) held.push_back(w.cast<double>() + Eigen::Vector3d::Constant(0.5));
        }
    if (held.size() < 6) return;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const auto& q : held) mean += q;
    mean /= double(held.size());
    Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
    for (const auto& q : held) spread += (q - mean) * (q - mean).transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
    solver.computeDirect(spread);
    if (solver.eigenvalues()(0) > kMaxFlatness * solver.eigenvalues()(1)) return;  // no plane there
    const Eigen::Vector3d n = solver.eigenvectors().col(0);
    const double apart = std::abs(n.dot(p - mean));
    const bool floor = std::abs(n.z()) > kFloorNormalZ;
    if (for_pair) (floor ? floors : walls).push_back(apart);
    auto& measured = regions[region];
    (floor ? measured.second : measured.first).push_back(apart);
  });
  SurfaceMisfit out;
  out.overall = larger_median(walls, floors, kMinPerKind);
  for (auto& [at, kinds] : regions)
    if (kinds.first.size() >= kMinPerRegionKind || kinds.second.size() >= kMinPerRegionKind)
      out.regions[at] = larger_median(kinds.first, kinds.second, kMinPerRegionKind);
  return out;
}

int pair_neighbourhood(double misfit, int neighbourhood) {
  return std::max(neighbourhood, int(std::ceil(2.0 * misfit - kQuantisation)));
}

}  // namespace lista::raycast
