// A PointCloud2's points as a scan of the data contract.
#pragma once

#include <lista_bag/messages.hpp>
#include <lista_io/pcd.hpp>

#include <array>

namespace lista::bag {

// x, y, z (float32 or float64) in the cloud's own frame, the intensity and
// the label by the same case-insensitive names as the PCD/PLY readers.
// Non-finite points are skipped and counted; a point's `index` is its place
// in the cloud. Throws lista::Error prefixed with `where` when the layout is
// inconsistent (fields past point_step, data shorter than the rows).
// `point_times`, when given, receives each kept point's time after the
// cloud's stamp in seconds if the cloud has a per-point time field (below),
// and stays empty if not.
io::ScanFile cloud_points(const Cloud& cloud, uint32_t scan_id, const std::string& where,
                          std::vector<double>* point_times = nullptr);

// The per-point time fields drivers write, matched without regard to case:
// Ouster "t" (uint32 ns after the stamp), Velodyne "time" (float32 s after
// the stamp), Livox "offset_time" (uint32 ns), Hesai "timestamp" (float64 s,
// absolute). Integer fields are nanoseconds, floating ones seconds; values
// past 1e6 s are absolute times (past 1e15, absolute nanoseconds).
inline constexpr std::array<const char*, 4> kTimeNames = {"t", "time", "offset_time", "timestamp"};

}  // namespace lista::bag
