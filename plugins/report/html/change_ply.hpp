// changes.ply: every object point in the common frame, coloured by status
// (removed red, added green, moved blue), with `object`, `mission` and
// `status` (0 removed, 1 added, 2 moved) as properties. Binary little endian,
// opened directly by CloudCompare, Open3D and MeshLab. Coordinates are the
// run's local frame: a `comment local_origin x y z` line gives what to add for
// the dataset's own (georeferenced) coordinates.
#pragma once

#include "report_model.hpp"

#include <Eigen/Core>

#include <string>

namespace lista::report {

// Returns the file content (the caller writes it atomically).
std::string change_ply(const ReportModel& model, const Eigen::Vector3d& local_origin);

}  // namespace lista::report
