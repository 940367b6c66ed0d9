// A PointCloud2's points as a scan of the data contract.
#pragma once

#include <lista_bag/messages.hpp>
#include <lista_io/pcd.hpp>

namespace lista::bag {

// x, y, z (float32 or float64) in the cloud's own frame, the intensity and
// the label by the same case-insensitive names as the PCD/PLY readers.
// Non-finite points are skipped and counted; a point's `index` is its place
// in the cloud. Throws lista::Error prefixed with `where` when the layout is
// inconsistent (fields past point_step, data shorter than the rows).
io::ScanFile cloud_points(const Cloud& cloud, uint32_t scan_id, const std::string& where);

}  // namespace lista::bag
