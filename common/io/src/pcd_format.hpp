// Internal: the parsed PCD header and a uniform view of the point data for
// all three encodings, shared by the scan reader and read_pcd_table.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace lista::io::detail {

struct PcdField {
  std::string name;
  int size = 4;
  char type = 'F';
  int count = 1;
  size_t offset = 0;  // byte offset inside a binary row
};

struct PcdData {
  std::vector<PcdField> fields;
  size_t points = 0;
  Eigen::Isometry3d viewpoint = Eigen::Isometry3d::Identity();
  bool viewpoint_identity = true;
  std::string encoding;  // ascii, binary, binary_compressed

  // Raw access: the bytes of element e of field f of point i are at
  // base[f] + i * step[f] + e * size (binary encodings).
  std::vector<const uint8_t*> base;
  std::vector<size_t> step;
  // ASCII: all values, row-major, `row_values` per point.
  std::vector<double> ascii;
  size_t row_values = 0;
  std::vector<size_t> ascii_column;  // first value column of field f

  std::string file_bytes;               // the whole file
  std::vector<uint8_t> decompressed;    // binary_compressed payload

  int find(const std::string& name) const;  // -1 if absent
  double value(int f, size_t i, int e = 0) const;
};

// Reads and parses `path`. Throws lista::Error "path[:line]: ..." when malformed.
void load_pcd(const std::string& path, PcdData& data);

}  // namespace lista::io::detail
