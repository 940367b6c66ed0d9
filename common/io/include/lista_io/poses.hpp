// poses.txt / poses_gt.txt: TUM (8 fields) or KITTI (12 fields) per line,
// told apart by field count; '#' starts a comment.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace lista::io {

struct PoseRecord {
  double timestamp = 0.0;  // TUM timestamp; KITTI: line index
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

enum class PoseFormat { tum, kitti };

// Throws lista::Error "file:line: ..." for a malformed line, a mixed layout or
// a rotation that is not orthonormal (tolerance 1e-3, then re-orthonormalised).
// `format`, when given, receives the layout found (tum for an empty file).
std::vector<PoseRecord> read_poses(const std::string& path, PoseFormat* format = nullptr);

void write_poses(const std::string& path, const std::vector<PoseRecord>& poses,
                 PoseFormat format = PoseFormat::tum);  // atomic

}  // namespace lista::io
