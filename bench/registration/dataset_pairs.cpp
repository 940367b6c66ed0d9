#include "dataset_pairs.hpp"

#include <lista/error.hpp>
#include <lista/parallel.hpp>
#include <lista_io/dataset.hpp>
#include <lista_io/pcd.hpp>

#include <map>

namespace lista::bench {

std::vector<ScanPair> dataset_pairs(const std::string& dataset_dir, const DatasetPairOptions& o) {
  // Poses and file lists first: only the scans the chosen pairs use are read.
  io::DatasetOptions poses_only;
  poses_only.load_points = false;
  const MissionSet set = io::read_dataset(dataset_dir, poses_only);
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

  // Each scan read once and prepared as align.posegraph's scan-to-scan
  // edges prepare it (scan_odometry.cpp): near points, downsampled.
  std::map<std::pair<size_t, size_t>, alignkit::Cloud> clouds;
  for (const Index& x : chosen) clouds[{x.mission, x.from}], clouds[{x.mission, x.to}];
  std::vector<std::pair<const std::pair<size_t, size_t>, alignkit::Cloud>*> todo;
  for (auto& entry : clouds) todo.push_back(&entry);
  parallel_for(todo.size(), o.threads, [&](size_t k) {
    const auto [m, s] = todo[k]->first;
    const Mission& mission = set.missions[m];
    const io::ScanFile file =
        io::read_scan(mission.scans[s].file, uint32_t(s), io::is_viewpoint_layout(mission.dir));
    todo[k]->second = alignkit::voxel_downsample_at_most(alignkit::within_range(file.points.xyz, o.max_range), o.voxel,
                                                      o.max_points);
  });

  std::vector<ScanPair> pairs;
  for (const Index& x : chosen) {
    const Mission& mission = set.missions[x.mission];
    ScanPair p;
    p.source = clouds.at({x.mission, x.to});
    p.target = clouds.at({x.mission, x.from});
    p.guess = mission.scans[x.from].pose.inverse() * mission.scans[x.to].pose;
    p.truth = mission.poses_gt[x.from].inverse() * mission.poses_gt[x.to];
    pairs.push_back(std::move(p));
  }
  return pairs;
}

}  // namespace lista::bench
