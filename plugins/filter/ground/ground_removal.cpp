#include "ground_removal.hpp"

#include <lista/error.hpp>
#include <lista/parallel.hpp>
#include <lista_pcl/convert.hpp>

#include <pcl/ModelCoefficients.h>
#include <lista_pcl/quiet.hpp>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/segmentation/sac_segmentation.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace lista::filter {
namespace {

using Cell = std::pair<int64_t, int64_t>;
Cell cell_of(const Eigen::Vector3f& p, double size) {
  return {int64_t(std::floor(p.x() / size)), int64_t(std::floor(p.y() / size))};
}

// Area of the convex hull of the footprint cells' centres (monotone chain):
// the plane's spread, robust to sparse LiDAR rings that leave cells empty.
double hull_area(const std::set<Cell>& cells, double cell) {
  std::vector<Eigen::Vector2d> p;
  for (const auto& [x, y] : cells) p.emplace_back((double(x) + 0.5) * cell, (double(y) + 0.5) * cell);
  if (p.size() < 3) return 0.0;  // std::set order is already x, then y
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); h[k++] = p[i++])
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0; h[k++] = p[i])
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
  double a = 0;
  for (size_t i = 0; i + 1 < k; ++i) a += h[i].x() * h[i + 1].y() - h[i + 1].x() * h[i].y();
  return std::abs(a) / 2.0;
}

// Ground points of one tile.
std::vector<uint32_t> ground_in_tile(const pcl::PointCloud<pcl::PointXYZ>::Ptr& cloud,
                                     const PointSet& points, const std::vector<uint32_t>& tile,
                                     const GroundConfig& c) {
  std::vector<uint32_t> ground;
  std::vector<uint32_t> remaining = tile;
  for (int attempt = 0; attempt < c.planes_per_tile && remaining.size() >= c.min_points; ++attempt) {
    pcl::SACSegmentation<pcl::PointXYZ> sac;  // fixed internal seed: deterministic
    sac.setOptimizeCoefficients(true);
    sac.setModelType(pcl::SACMODEL_PERPENDICULAR_PLANE);
    sac.setMethodType(pcl::SAC_RANSAC);
    sac.setAxis(Eigen::Vector3f::UnitZ());
    sac.setEpsAngle(c.max_slope_deg * M_PI / 180.0);
    sac.setDistanceThreshold(c.distance);
    sac.setMaxIterations(c.max_iterations);
    sac.setInputCloud(cloud);
    auto idx = std::make_shared<pcl::Indices>(remaining.begin(), remaining.end());
    sac.setIndices(idx);
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coeff;
    sac.segment(inliers, coeff);
    if (inliers.indices.size() < c.min_points || coeff.values.size() != 4) break;

    Eigen::Vector4f plane(coeff.values[0], coeff.values[1], coeff.values[2], coeff.values[3]);
    if (plane.z() < 0) plane = -plane;  // normal up: negative distance = under the plane
    const float norm = plane.head<3>().norm();
    if (!(norm > 0) || std::acos(std::min(1.f, plane.z() / norm)) > c.max_slope_deg * M_PI / 180.0 + 1e-3)
      break;
    plane /= norm;

    // The plane's inliers fall into patches: footprint cells linked across
    // gaps of at most one empty cell. Each patch is judged on its own, so a
    // floor sheet and a deck at the same height elsewhere in the tile (or
    // several objects' parts at one height) are not one "plane".
    std::map<Cell, int> patch_of;
    for (auto i : inliers.indices) patch_of.emplace(cell_of(points.xyz[i], c.footprint_cell), -1);
    std::vector<std::set<Cell>> patches;
    for (auto& [start, id] : patch_of) {
      if (id >= 0) continue;
      id = int(patches.size());
      patches.emplace_back();
      std::vector<Cell> todo{start};
      while (!todo.empty()) {
        const Cell q = todo.back();
        todo.pop_back();
        patches.back().insert(q);
        for (int64_t dx = -2; dx <= 2; ++dx)
          for (int64_t dy = -2; dy <= 2; ++dy) {
            auto it = patch_of.find({q.first + dx, q.second + dy});
            if (it != patch_of.end() && it->second < 0) {
              it->second = id;
              todo.push_back(it->first);
            }
          }
      }
    }
    std::vector<size_t> inliers_in(patches.size(), 0), below(patches.size(), 0);
    for (auto i : inliers.indices) ++inliers_in[size_t(patch_of.at(cell_of(points.xyz[i], c.footprint_cell)))];
    for (auto i : tile) {
      const auto& p = points.xyz[i];
      if (plane.head<3>().dot(p) + plane.w() >= -2.0 * c.distance) continue;
      auto it = patch_of.find(cell_of(p, c.footprint_cell));
      if (it != patch_of.end()) ++below[size_t(it->second)];
    }
    // Floor in a change cloud (misalignment, drift) is a broad sheet; a flat
    // object with nothing visible under it (pallet, cart deck, mat) is small.
    std::vector<char> is_ground(patches.size());
    for (size_t k = 0; k < patches.size(); ++k)
      is_ground[k] = double(below[k]) <= c.max_below_fraction * double(inliers_in[k]) &&
                     (c.min_area <= 0 || hull_area(patches[k], c.footprint_cell) >= c.min_area);
    for (auto i : inliers.indices)
      if (is_ground[size_t(patch_of.at(cell_of(points.xyz[i], c.footprint_cell)))]) ground.push_back(uint32_t(i));

    // Try the next plane on what is left (a lower level, or the floor under a table).
    std::vector<uint32_t> sorted_in(inliers.indices.begin(), inliers.indices.end());
    std::sort(sorted_in.begin(), sorted_in.end());
    std::vector<uint32_t> rest;
    std::set_difference(remaining.begin(), remaining.end(), sorted_in.begin(), sorted_in.end(),
                        std::back_inserter(rest));
    remaining.swap(rest);
  }
  return ground;
}

}  // namespace

std::vector<uint32_t> find_ground(const PointSet& points, const GroundConfig& c, int threads) {
  if (!(c.tile_size > 0) || !(c.distance > 0) || !(c.footprint_cell > 0))
    throw Error("tile_size, distance and footprint_cell must be > 0");
  if (points.empty()) return {};
  // A tile with no horizontal plane (only walls or objects) is an expected
  // outcome here, but PCL prints it as an error on stderr once per tile.
  // PCL has only a process-wide switch: quiet it while this call runs.
  pcl_convert::QuietPcl quiet;
  std::map<Cell, std::vector<uint32_t>> tiles;  // ordered: deterministic
  for (uint32_t i = 0; i < points.size(); ++i) tiles[cell_of(points.xyz[i], c.tile_size)].push_back(i);
  std::vector<const std::vector<uint32_t>*> list;
  for (auto& [k, v] : tiles) list.push_back(&v);

  auto cloud = pcl_convert::to_xyz(points);
  std::vector<std::vector<uint32_t>> found(list.size());
  parallel_for(list.size(), threads, [&](size_t t) { found[t] = ground_in_tile(cloud, points, *list[t], c); });

  std::vector<uint32_t> ground;
  for (auto& f : found) ground.insert(ground.end(), f.begin(), f.end());
  std::sort(ground.begin(), ground.end());
  return ground;
}

}  // namespace lista::filter
