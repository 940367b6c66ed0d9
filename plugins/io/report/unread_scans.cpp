#include "unread_scans.hpp"

#include <lista/parallel.hpp>
#include <lista_geometry/voxel_key.hpp>
#include <lista_io/dataset.hpp>
#include <lista_io/pcd.hpp>

#include <cmath>
#include <filesystem>
#include <unordered_map>

namespace lista::io {

UnreadScans add_unread_scans(const MissionSet& missions, Built& b, double cell, int threads) {
  UnreadScans out;
  for (size_t m = 0; m < missions.missions.size(); ++m) {
    const Mission& mission = missions.missions[m];
    std::vector<size_t> unread;
    for (size_t s = 0; s < mission.scans.size(); ++s) {
      const Scan& scan = mission.scans[s];
      if ((!scan.points || scan.points->empty()) && scan.points_in_file == 0 && std::filesystem::is_regular_file(scan.file))
        unread.push_back(s);
    }
    ChangeCloud& cloud = b.clouds.at(m);
    if (unread.empty() || cloud.size() == 0) continue;
    // The change cells, in the run's local frame (rows carry the origin).
    std::unordered_map<uint64_t, int32_t> object_of;
    for (size_t i = 0; i < cloud.size(); ++i) {
      const Eigen::Vector3d p = Eigen::Vector3d(cloud.x[i], cloud.y[i], cloud.z[i]) - missions.origin;
      object_of.emplace(geometry::voxel_key_of(p, cell), cloud.object[i]);
    }
    // The VIEWPOINT layout (no poses.txt) stores map-frame points.
    const bool map_frame = !mission.dir.empty() && io::is_viewpoint_layout(mission.dir);
    std::vector<ChangeCloud> found(unread.size());
    parallel_for(unread.size(), threads, [&](size_t k) {
      const size_t s = unread[k];
      const io::ScanFile file = io::read_scan(mission.scans[s].file, uint32_t(s), map_frame);
      const Eigen::Isometry3d to_common = mission.sensor_to_common(s);
      for (size_t i = 0; i < file.points.size(); ++i) {
        const Eigen::Vector3f& q = file.points.xyz[i];
        if (q.squaredNorm() == 0.0f) continue;  // a missing return (io.missions drops these too)
        const Eigen::Vector3d p = to_common * q.cast<double>();
        const auto it = object_of.find(geometry::voxel_key_of(p, cell));
        if (it == object_of.end()) continue;
        found[k].push_back((p + missions.origin).cast<float>(), uint32_t(s), file.points.index[i], it->second);
      }
    });
    out.scans += unread.size();
    for (const ChangeCloud& f : found) {
      cloud.append(f);
      out.points += f.size();
    }
  }
  return out;
}

}  // namespace lista::io
