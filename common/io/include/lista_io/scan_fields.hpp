// How any scan reader (PCD, PLY, a bag's PointCloud2) names its optional
// point fields and turns a label value into the contract's uint32 id.
#pragma once

#include <lista_io/pcd.hpp>

#include <array>
#include <cmath>

namespace lista::io {

// Where a point's intensity is, best first (field names matched without
// regard to case): PCL's name, CloudCompare's scalar field, and a driver's
// calibrated reflectivity when that is all.
inline constexpr std::array<const char*, 3> kIntensityNames = {"intensity", "scalar_intensity", "reflectivity"};

// A label read as a number: the contract's labels are uint32 object ids.
// Another tool's -1, 1.5 or NaN (casting them would be undefined) marks the
// scan's labels unusable: ScanFile::bad_labels, and the channel is dropped
// (a run does not need labels; scoring says the scan has none).
inline uint32_t to_label(double v, ScanFile& s) {
  if (v >= 0.0 && v <= 4294967295.0 && v == std::floor(v)) return static_cast<uint32_t>(v);
  s.bad_labels = true;
  return 0;
}
inline void drop_bad_labels(ScanFile& s) {
  if (s.bad_labels) s.points.label.clear();
}

}  // namespace lista::io
