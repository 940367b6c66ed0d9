#include <lista_raycast/seen_through.hpp>

#include <lista/parallel.hpp>
#include <lista_geometry/range_image.hpp>
#include <lista_geometry/stations.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <cmath>
#include <unordered_map>
#include <vector>

namespace lista::raycast {

namespace {

// A cell of changed points: its first point (common frame), the side its
// scan saw it from, and its points.
struct Cell {
  Eigen::Vector3d centre;
  Eigen::Vector3d normal;
  std::vector<uint32_t> points;
};

std::vector<Cell> cells_of(const Mission& mission, const PointSet& changes, double size) {
  std::vector<Cell> cells;
  std::unordered_map<uint64_t, size_t> index;
  for (size_t i = 0; i < changes.size(); ++i) {
    if (changes.changed_against[i] & seen_free_in_own_mission) continue;
    const Eigen::Vector3d p = changes.xyz[i].cast<double>();
    const auto [it, added] = index.try_emplace(geometry::voxel_key_of(p, size), cells.size());
    if (added) {
      const Eigen::Vector3d origin = mission.sensor_to_common(changes.scan[i]).translation();
      cells.push_back({p, (origin - p).normalized(), {}});
    }
    cells[it->second].points.push_back(uint32_t(i));
  }
  return cells;
}

}  // namespace

void mark_seen_through(const Mission& mission, PointSet& changes, const VolumetricConfig& config, int threads) {
  if (changes.empty() || !changes.has_changed_against() || geometry::scanned_from_stations(mission)) return;
  // Two voxels: the reach of a beam "at" the point, how far behind it the
  // place is asked about, and twice that beyond for range noise.
  const double rho = 2.0 * config.resolution, depth = rho, margin = 2.0 * rho;
  const std::vector<Cell> cells = cells_of(mission, changes, rho);
  if (cells.empty()) return;
  const size_t n = cells.size();
  std::vector<int8_t> votes(mission.scans.size() * n, 0);  // +1 present, -1 seen through
  parallel_for(mission.scans.size(), threads, [&](size_t s) {
    const Scan& scan = mission.scans[s];
    if (!scan.points || scan.points->empty()) return;
    const geometry::RangeImage image(*scan.points);
    const Eigen::Isometry3d to_sensor = mission.sensor_to_common(s).inverse();
    for (size_t c = 0; c < n; ++c) {
      const Eigen::Vector3d q = to_sensor * cells[c].centre;
      if (config.max_range > 0.0 && q.norm() > config.max_range) continue;
      const auto vote = image.look(q, to_sensor.linear() * cells[c].normal, depth, rho, margin);
      votes[s * n + c] = vote == geometry::RangeImage::Vote::present ? 1
                         : vote == geometry::RangeImage::Vote::see_through ? -1 : 0;
    }
  });
  for (size_t c = 0; c < n; ++c) {
    // A thing that moved through was there for a while, once: the scans
    // that saw it are one run in time, with no look through it between
    // them. A wire cart or an open frame that stood still is hit by some
    // scans and seen through by others in any order.
    int present = 0, through = 0;
    bool one_run = true, run_ended = false;
    for (size_t s = 0; s < mission.scans.size(); ++s) {
      const int8_t v = votes[s * n + c];
      if (v > 0) {
        one_run = one_run && !run_ended;
        ++present;
      } else if (v < 0) {
        run_ended = present > 0;
        ++through;
      }
    }
    if (through == 0 || through < present || !one_run) continue;
    for (uint32_t i : cells[c].points) changes.changed_against[i] |= seen_free_in_own_mission;
  }
}

}  // namespace lista::raycast
