// Scan pairs of a recorded dataset (data contract, sect. 1) for
// lista-bench registration: each scan with the next `steps` scans of its
// mission, started from the odometry (poses.txt) and scored against the
// truth (poses_gt.txt), with the points align.posegraph's scan-to-scan
// edges use (within `max_range` of the sensor, downsampled to `voxel`,
// coarser until at most `max_points` are left).
#pragma once

#include <lista_alignkit/cloud_ops.hpp>

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace lista::bench {

struct ScanPair {
  alignkit::Cloud source, target;
  Eigen::Isometry3d truth, guess;  // source -> target
};

struct DatasetPairOptions {
  int steps = 2;               // align.posegraph's scan_edges
  double max_range = 40.0;     // m; its scan_range
  double voxel = 0.1;          // m; its scan_voxel
  size_t max_points = 15000;   // its scan_points
  size_t max_pairs = 0;        // spread evenly over the dataset; 0: all
  int threads = 2;             // for reading and preparing the scans
};

// Throws lista::Error when no mission has poses_gt.txt (nothing to score).
std::vector<ScanPair> dataset_pairs(const std::string& dataset_dir, const DatasetPairOptions& options);

}  // namespace lista::bench
