// Point cloud files of the data contract: PCD (ascii, binary,
// binary_compressed), PLY (ascii, binary little/big endian) and KITTI .bin.
#pragma once

#include <lista/points.hpp>

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lista::io {

// One scan file as read. `points` holds finite points only; their `index` is
// their position in the file (non-finite ones counted), `scan` = scan_id.
struct ScanFile {
  PointSet points;
  uint32_t points_in_file = 0;
  size_t skipped_nonfinite = 0;
  std::optional<Eigen::Isometry3d> viewpoint;  // PCD VIEWPOINT, if not identity
  bool bad_labels = false;  // a `label` that is no uint32 integer (-1, 1.5, NaN): the channel is dropped
};

// Reads .pcd, .ply or .bin by extension. Throws lista::Error naming the file
// (and line for ASCII) on anything malformed. With `map_frame` (the VIEWPOINT
// layout: a .pcd's points in the map frame, its VIEWPOINT the sensor pose),
// points come back in the sensor frame, transformed in double before the
// float conversion (georeferenced map frames); float32 coordinates around a
// VIEWPOINT 2^17 m or more from zero (spacing over 1 cm) are an error.
ScanFile read_scan(const std::string& path, uint32_t scan_id = 0, bool map_frame = false);

// The VIEWPOINT of a .pcd file, read from its header alone (nullopt when it
// is the identity or absent), as read_scan would give it: lets a reader
// choose which map-frame scans to read before reading any points.
std::optional<Eigen::Isometry3d> read_pcd_viewpoint(const std::string& path);

enum class PcdEncoding { ascii, binary, binary_compressed };

// A column of a PCD file to write: F = float32, U = uint32, I = int32.
struct PcdColumn {
  std::string name;
  char type = 'F';
  const void* data = nullptr;  // n values of that type
};

// Writes n points with the given columns. x, y, z are usually the first three
// float columns. Atomic: writes "<path>.tmp" then renames.
void write_pcd(const std::string& path, size_t n, const std::vector<PcdColumn>& columns,
               PcdEncoding encoding = PcdEncoding::binary,
               const Eigen::Isometry3d& viewpoint = Eigen::Isometry3d::Identity());

// Convenience: x y z [intensity] [label] of a PointSet (sensor-frame scans).
void write_scan_pcd(const std::string& path, const PointSet& points,
                    PcdEncoding encoding = PcdEncoding::binary);

// A whole PCD file as named columns (for readers of changes/<mission>.pcd).
struct PcdTable {
  size_t size = 0;
  std::vector<std::string> names;
  std::vector<char> types;                  // 'F', 'U' or 'I' (after widening to 4 bytes)
  std::vector<std::vector<double>> values;  // one vector per column
  int column(const std::string& name) const;  // -1 if absent
};
PcdTable read_pcd_table(const std::string& path);

}  // namespace lista::io
