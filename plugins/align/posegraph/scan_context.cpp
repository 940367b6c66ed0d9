#include "scan_context.hpp"

#include <lista/error.hpp>

#include <cmath>

namespace lista::align {

ScanContext make_scan_context(const std::vector<Eigen::Vector3f>& points,
                              const ScanContextOptions& o) {
  if (o.rings < 1 || o.sectors < 4 || o.max_radius <= 0.0 || o.max_height <= o.min_height)
    throw Error("scan context: need rings >= 1, sectors >= 4, max_radius > 0 and max_height > min_height");
  ScanContext sc;
  sc.grid = Eigen::MatrixXf::Zero(o.rings, o.sectors);
  const double two_pi = 2.0 * M_PI;
  for (const auto& p : points) {
    if (p.z() < o.min_height || p.z() > o.max_height) continue;
    const double r = std::hypot(p.x(), p.y());
    if (r >= o.max_radius || r < 1e-6) continue;
    const int ring = std::min(o.rings - 1, static_cast<int>(r / o.max_radius * o.rings));
    const double angle = std::atan2(p.y(), p.x()) + M_PI;  // [0, 2pi]
    const int sector = std::min(o.sectors - 1, static_cast<int>(angle / two_pi * o.sectors));
    // Height above the band floor, so an occupied bin is never 0.
    const float h = static_cast<float>(p.z() - o.min_height) + 1e-3f;
    float& cell = sc.grid(ring, sector);
    if (h > cell) cell = h;
  }
  sc.ring_key.resize(o.rings);
  for (int r = 0; r < o.rings; ++r)
    sc.ring_key(r) = static_cast<float>((sc.grid.row(r).array() > 0.f).count()) / o.sectors;
  return sc;
}

ScanContextMatch compare(const ScanContext& ref, const ScanContext& query) {
  ScanContextMatch best;
  const int rings = static_cast<int>(ref.grid.rows()), sectors = static_cast<int>(ref.grid.cols());
  if (query.grid.rows() != rings || query.grid.cols() != sectors)
    throw Error("scan context: descriptors of different sizes cannot be compared");
  // Column norms once; a column with norm 0 is empty.
  const Eigen::VectorXf ref_norm = ref.grid.colwise().norm();
  const Eigen::VectorXf query_norm = query.grid.colwise().norm();
  for (int shift = 0; shift < sectors; ++shift) {
    double sum = 0.0;
    int shared = 0;
    for (int j = 0; j < sectors; ++j) {
      const int jr = (j + shift) % sectors;
      if (ref_norm(jr) <= 0.f || query_norm(j) <= 0.f) continue;
      sum += ref.grid.col(jr).dot(query.grid.col(j)) / (ref_norm(jr) * query_norm(j));
      ++shared;
    }
    if (shared * 4 < sectors) continue;
    const double distance = 1.0 - sum / shared;
    if (distance < best.distance) {
      best.distance = distance;
      best.shift = shift;
    }
  }
  // Column j of the query holds what the reference sees at column j + shift:
  // the query frame is turned by shift sectors in the reference frame.
  double yaw = (best.shift + 0.0) * 2.0 * M_PI / sectors;
  if (yaw > M_PI) yaw -= 2.0 * M_PI;
  best.yaw = yaw;
  return best;
}

}  // namespace lista::align
