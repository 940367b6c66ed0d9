#include <lista_raycast/misfit.hpp>
#include <lista_geometry/order_statistics.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <vector>

namespace lista::raycast {

namespace {
constexpr int kWindow = 2;               // voxels around a point searched for the other's surface
constexpr size_t kSamples = 8192;        // points of the mission measured
constexpr size_t kMinPerKind = 50;       // fewer walls (or floors) than this: that kind is not measured
constexpr double kMaxFlatness = 0.3;     // smallest / middle spread of a plane's voxels
constexpr double kFloorNormalZ = 0.7;    // |n.z| above this: a floor or a ceiling, else a wall
constexpr double kQuantisation = 0.5;    // voxels: what a point's place inside its voxel alone gives

}  // namespace

double surface_misfit(const Mission& mission, const OccupancyMap& other, const VolumetricConfig& config) {
  const double inv_res = 1.0 / config.resolution;
  const float occupied = logodds(config.occupied_threshold);
  auto reader = other.reader();
  size_t total = 0;
  for (const Scan& s : mission.scans) total += s.points ? s.points->size() : 0;
  const size_t step = std::max<size_t>(1, total / kSamples);
  std::vector<double> walls, floors;
  std::vector<Eigen::Vector3d> held;
  size_t k = 0;
  for (size_t i = 0; i < mission.scans.size(); ++i) {
    if (!mission.scans[i].points) continue;
    const PointSet& pts = *mission.scans[i].points;
    const Eigen::Affine3d to_index = Eigen::Scaling(inv_res) * mission.sensor_to_common(i);
    for (size_t j = 0; j < pts.size(); ++j, ++k) {
      if (k % step) continue;
      const Eigen::Vector3d p = to_index * pts.xyz[j].cast<double>();
      const Voxel v = voxel_of(p);
      held.clear();
      float l;
      for (int dz = -kWindow; dz <= kWindow; ++dz)
        for (int dy = -kWindow; dy <= kWindow; ++dy)
          for (int dx = -kWindow; dx <= kWindow; ++dx) {
            const Voxel w(v.x() + dx, v.y() + dy, v.z() + dz);
            if (reader->logodds(w, l) && l > occupied) held.push_back(w.cast<double>() + Eigen::Vector3d::Constant(0.5));
          }
      if (held.size() < 6) continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& q : held) mean += q;
      mean /= double(held.size());
      Eigen::Matrix3d spread = Eigen::Matrix3d::Zero();
      for (const auto& q : held) spread += (q - mean) * (q - mean).transpose();
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
      solver.computeDirect(spread);
      if (solver.eigenvalues()(0) > kMaxFlatness * solver.eigenvalues()(1)) continue;  // no plane there
      const Eigen::Vector3d n = solver.eigenvectors().col(0);
      (std::abs(n.z()) > kFloorNormalZ ? floors : walls).push_back(std::abs(n.dot(p - mean)));
    }
  }
  double misfit = 0.0;
  for (auto* kind : {&walls, &floors})
    if (kind->size() >= kMinPerKind) misfit = std::max(misfit, geometry::median(*kind));
  return misfit;
}

int pair_neighbourhood(double misfit, int neighbourhood) {
  return std::max(neighbourhood, int(std::ceil(2.0 * misfit - kQuantisation)));
}

}  // namespace lista::raycast
