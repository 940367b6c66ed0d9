#include "unread_scans.hpp"

#include <lista/parallel.hpp>
#include <lista_io/pcd.hpp>

#include <cmath>
#include <filesystem>
#include <unordered_map>

namespace lista::report {

namespace {

uint64_t cell_key(const Eigen::Vector3d& p, double cell) {
  const auto axis = [&](double v) { return uint64_t(int64_t(std::floor(v / cell)) + (int64_t(1) << 20)) & 0x1FFFFF; };
  return axis(p.x()) << 42 | axis(p.y()) << 21 | axis(p.z());
}

}  // namespace

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
      object_of.emplace(cell_key(p, cell), cloud.object[i]);
    }
    // The VIEWPOINT layout (no poses.txt) stores map-frame points.
    const bool map_frame = !mission.dir.empty() && !std::filesystem::exists(std::filesystem::path(mission.dir) / "poses.txt");
    std::vector<ChangeCloud> found(unread.size());
    parallel_for(unread.size(), threads, [&](size_t k) {
      const size_t s = unread[k];
      const io::ScanFile file = io::read_scan(mission.scans[s].file, uint32_t(s), map_frame);
      const Eigen::Isometry3d to_common = mission.sensor_to_common(s);
      for (size_t i = 0; i < file.points.size(); ++i) {
        const Eigen::Vector3f& q = file.points.xyz[i];
        if (q.squaredNorm() == 0.0f) continue;  // a missing return (io.missions drops these too)
        const Eigen::Vector3d p = to_common * q.cast<double>();
        const auto it = object_of.find(cell_key(p, cell));
        if (it == object_of.end()) continue;
        const Eigen::Vector3d at = p + missions.origin;
        found[k].x.push_back(float(at.x()));
        found[k].y.push_back(float(at.y()));
        found[k].z.push_back(float(at.z()));
        found[k].scan.push_back(uint32_t(s));
        found[k].index.push_back(file.points.index[i]);
        found[k].object.push_back(it->second);
      }
    });
    out.scans += unread.size();
    for (const ChangeCloud& f : found) {
      cloud.x.insert(cloud.x.end(), f.x.begin(), f.x.end());
      cloud.y.insert(cloud.y.end(), f.y.begin(), f.y.end());
      cloud.z.insert(cloud.z.end(), f.z.begin(), f.z.end());
      cloud.scan.insert(cloud.scan.end(), f.scan.begin(), f.scan.end());
      cloud.index.insert(cloud.index.end(), f.index.begin(), f.index.end());
      cloud.object.insert(cloud.object.end(), f.object.begin(), f.object.end());
      out.points += f.size();
    }
  }
  return out;
}

}  // namespace lista::report
