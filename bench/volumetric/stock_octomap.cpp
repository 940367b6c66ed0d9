#include "stock_octomap.hpp"

#include <lista_raycast/dda.hpp>

#include <octomap/OcTree.h>

#include <algorithm>
#include <chrono>

StockResult run_stock_octomap(const lista::Mission& mission, const lista::raycast::VolumetricConfig& c,
                              size_t max_scans, const std::function<void(size_t, size_t)>& progress) {
  using namespace lista::raycast;
  octomap::OcTree tree(c.resolution);
  tree.setProbHit(c.prob_hit);
  tree.setProbMiss(c.prob_miss);
  tree.setClampingThresMin(c.clamping_min);
  tree.setClampingThresMax(c.clamping_max);
  StockResult r;
  r.scans = max_scans ? std::min(max_scans, mission.scans.size()) : mission.scans.size();
  const double inv_res = 1.0 / c.resolution;
  for (size_t i = 0; i < r.scans; ++i) {
    const lista::PointSet& pts = *mission.scans[i].points;
    const Eigen::Isometry3d pose = mission.sensor_to_common(i);
    octomap::Pointcloud cloud;
    cloud.reserve(pts.size());
    for (const auto& p : pts.xyz) {
      const Eigen::Vector3d q = pose * p.cast<double>();
      cloud.push_back(static_cast<float>(q.x()), static_cast<float>(q.y()), static_cast<float>(q.z()));
    }
    const Eigen::Vector3d o = pose.translation();
    const auto t0 = std::chrono::steady_clock::now();
    tree.insertPointCloud(cloud, octomap::point3d(o.x(), o.y(), o.z()), c.max_range > 0 ? c.max_range : -1.0);
    r.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // Visits with the shared DDA (untimed), so visits/s compare like with like.
    const Eigen::Vector3d oi = o * inv_res;
    for (const auto& p : pts.xyz) {
      Eigen::Vector3d e = pose * p.cast<double>() * inv_res;
      clip_ray(oi, e, c.max_range > 0 ? c.max_range * inv_res : 0.0);
      r.voxel_visits += walk_ray(oi, e, [](const Voxel&) {});
    }
    r.rays += pts.size();
    if (progress) progress(i + 1, r.scans);
  }
  r.leaf_nodes = tree.getNumLeafNodes();
  return r;
}
