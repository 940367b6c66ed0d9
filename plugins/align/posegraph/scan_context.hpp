// Scan Context (Kim & Kim, IROS 2018): a polar grid (rings x sectors) around
// the sensor holding the highest point in each bin, compared under every
// column shift so that a revisit is recognised whatever the heading.
// Heights are taken relative to the sensor inside a band [min_height, max_height] so the
// same parameters work for a vehicle LiDAR outdoors and an indoor sensor
// whose wide vertical field of view sees the ceiling everywhere (points above
// max_height are ignored instead of saturating every bin).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace lista::align {

struct ScanContextOptions {
  int rings = 20;
  int sectors = 60;
  double max_radius = 40.0;  // m; points farther away are ignored
  double min_height = -3.0;       // m, relative to the sensor, in the levelled frame
  double max_height = 1.5;        // m, relative to the sensor
};

struct ScanContext {
  Eigen::MatrixXf grid;      // rings x sectors; 0 = empty, else height above min_height
  Eigen::VectorXf ring_key;  // per ring: share of occupied sectors (yaw invariant)
};

// Points in a gravity-levelled frame centred on the sensor (z up).
ScanContext make_scan_context(const std::vector<Eigen::Vector3f>& levelled_points,
                              const ScanContextOptions& options);

struct ScanContextMatch {
  double distance = 1.0;  // mean column cosine distance in [0, 1]; 1 = nothing in common
  int shift = 0;          // best column shift
  // Yaw of the query frame in the reference frame (rad): p_ref ~= Rz(yaw) * p_query.
  double yaw = 0.0;
};

// Compares `query` against `reference` under every column shift. Columns empty
// in either descriptor are skipped; fewer than a quarter shared columns is no match.
ScanContextMatch compare(const ScanContext& reference, const ScanContext& query);

}  // namespace lista::align
