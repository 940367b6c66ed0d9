#include "dataset_pairs.hpp"

#include <lista/error.hpp>
#include <lista_io/dataset.hpp>

namespace lista::bench {

namespace {

// As align.posegraph's scan-to-scan edges prepare a scan (scan_odometry.cpp).
align::Cloud edge_points(const Scan& scan, const DatasetPairOptions& o) {
  align::Cloud near;
  if (!scan.points) return near;
  const float r2 = static_cast<float>(o.max_range * o.max_range);
  for (const auto& p : scan.points->xyz)
    if (p.squaredNorm() <= r2) near.push_back(p);
  double voxel = o.voxel;
  align::Cloud out = align::voxel_downsample(near, voxel);
  while (out.size() > o.max_points) {
    voxel *= 1.25;
    out = align::voxel_downsample(near, voxel);
  }
  return out;
}

}  // namespace

std::vector<ScanPair> dataset_pairs(const std::string& dataset_dir, const DatasetPairOptions& o) {
  io::DatasetOptions read;
  read.threads = o.threads;
  const MissionSet set = io::read_dataset(dataset_dir, read);
  struct Index {
    size_t mission, from, to;
  };
  std::vector<Index> all;
  for (size_t m = 0; m < set.missions.size(); ++m) {
    const Mission& mission = set.missions[m];
    if (mission.poses_gt.size() != mission.scans.size()) continue;
    for (size_t i = 0; i < mission.scans.size(); ++i)
      for (size_t k = 1; k <= size_t(o.steps) && i + k < mission.scans.size(); ++k) all.push_back({m, i, i + k});
  }
  if (all.empty())
    throw Error(dataset_dir + ": no mission with poses_gt.txt and two scans: nothing to score registrations against");
  std::vector<Index> chosen = all;
  if (o.max_pairs > 0 && all.size() > o.max_pairs) {
    chosen.clear();
    for (size_t k = 0; k < o.max_pairs; ++k) chosen.push_back(all[k * all.size() / o.max_pairs]);
  }
  std::vector<ScanPair> pairs;
  for (const Index& x : chosen) {
    const Mission& mission = set.missions[x.mission];
    ScanPair p;
    p.source = edge_points(mission.scans[x.to], o);
    p.target = edge_points(mission.scans[x.from], o);
    p.guess = mission.scans[x.from].pose.inverse() * mission.scans[x.to].pose;
    p.truth = mission.poses_gt[x.from].inverse() * mission.poses_gt[x.to];
    p.name = mission.name + " " + std::to_string(x.from) + "->" + std::to_string(x.to);
    pairs.push_back(std::move(p));
  }
  return pairs;
}

}  // namespace lista::bench
