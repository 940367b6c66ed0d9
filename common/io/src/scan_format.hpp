// Internal: building a ScanFile from any reader's values.
#pragma once

#include <lista_io/pcd.hpp>
#include <lista_io/scan_fields.hpp>

#include <array>
#include <cmath>

namespace lista::io::detail {

// Appends file point `index` if finite; counts it as skipped otherwise.
inline void add_point(ScanFile& s, uint32_t scan_id, uint32_t index, float x, float y, float z,
                      bool has_i, float intensity, bool has_l, uint32_t label) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
    ++s.skipped_nonfinite;
    return;
  }
  s.points.xyz.emplace_back(x, y, z);
  if (has_i) s.points.intensity.push_back(intensity);
  if (has_l) s.points.label.push_back(label);
  s.points.scan.push_back(scan_id);
  s.points.index.push_back(index);
}

ScanFile read_ply(const std::string& path, uint32_t scan_id);

using io::kIntensityNames;
using io::to_label;
using io::drop_bad_labels;

}  // namespace lista::io::detail
