// The transforms align.given can apply: read from a file, or estimated from
// each mission's poses against its true poses (poses_gt.txt).
#pragma once

#include <lista/missions.hpp>

#include <map>
#include <string>

namespace lista::align {

// Reads "<mission> <16 numbers, 4x4 row-major>" or "<mission> <12 numbers,
// 3x4 [R|t] row-major>" per line; '#' starts a comment. Errors name
// "file:line". The rotation must be orthonormal (tolerance 1e-3).
std::map<std::string, Eigen::Isometry3d> read_transform_file(const std::string& path);

// The rigid T (map -> world) minimising sum_i |T * P_i - G_i|^2 over the scans'
// sensor origins and unit axis tips (so rotations count too and one scan is
// enough). Throws if the mission has no poses_gt.
Eigen::Isometry3d map_to_world_from_gt(const Mission& mission);

}  // namespace lista::align
