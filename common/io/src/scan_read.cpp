// read_scan: dispatch by extension; the PCD and KITTI .bin scan readers.
#include "pcd_format.hpp"
#include "scan_format.hpp"
#include "text_util.hpp"

#include <lista/error.hpp>
#include <lista_io/pcd.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <new>
#include <stdexcept>

namespace lista::io {

namespace {

std::string lower_extension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Every point through PcdData::value (any field type), moved by `to_sensor`
// in double before the float conversion: map-frame points of the VIEWPOINT
// layout may lie hundreds of km from zero (georeferenced), where a float
// keeps only decimetres.
void read_by_value(const detail::PcdData& d, int fx, int fy, int fz, int fi, int fl,
                   const Eigen::Isometry3d& to_sensor, uint32_t scan_id, ScanFile& s) {
  for (size_t i = 0; i < d.points; ++i) {
    const Eigen::Vector3d p = to_sensor * Eigen::Vector3d(d.value(fx, i), d.value(fy, i), d.value(fz, i));
    const float in = fi >= 0 ? static_cast<float>(d.value(fi, i)) : 0.f;
    const uint32_t lb = fl >= 0 ? detail::to_label(d.value(fl, i), s) : 0u;
    detail::add_point(s, scan_id, uint32_t(i), float(p.x()), float(p.y()), float(p.z()), fi >= 0, in, fl >= 0, lb);
  }
}

// Float32 map-frame coordinates around a sensor far from zero lost their
// precision in the file already: an error, not a silent 0.5 m grid. Spacing
// accepted near the sensor: 1 cm, i.e. within 2^17 m of zero; judged at the
// sensor (VIEWPOINT), not per point: a stray return far out is the sensor's
// noise, not the file's precision.
void check_map_frame_precision(const std::string& path, const detail::PcdData& d, int fx, int fy, int fz) {
  constexpr double kFloat32Reach = 131072.0;
  const bool float32 = d.fields[fx].size == 4 || d.fields[fy].size == 4 || d.fields[fz].size == 4;
  const double sensor_range = d.viewpoint.translation().cwiseAbs().maxCoeff();
  if (!float32 || sensor_range < kFloat32Reach) return;
  char where[64];
  std::snprintf(where, sizeof where, "%.0f", sensor_range);
  throw Error(path + ": map-frame float32 coordinates around a sensor " + where +
              " m from zero keep only decimetres; store x y z as F8 (double), or the points in the sensor frame "
              "with poses.txt");
}

ScanFile read_pcd_scan(const std::string& path, uint32_t scan_id, bool map_frame) {
  detail::PcdData d;
  detail::load_pcd(path, d);
  const int fx = d.find("x"), fy = d.find("y"), fz = d.find("z");
  if (fx < 0 || fy < 0 || fz < 0) throw Error(path + ": PCD file lacks one of the fields x, y, z");
  int fi = -1;
  for (const char* name : detail::kIntensityNames)
    if (fi < 0) fi = d.find(name);
  const int fl = d.find("label");
  ScanFile s;
  const size_t n = d.points;
  s.points_in_file = static_cast<uint32_t>(n);
  s.points.reserve(n);
  if (fi >= 0) s.points.intensity.reserve(n);
  if (fl >= 0) s.points.label.reserve(n);
  if (map_frame) {
    check_map_frame_precision(path, d, fx, fy, fz);
    read_by_value(d, fx, fy, fz, fi, fl, d.viewpoint.inverse(), scan_id, s);
  } else if (d.encoding != "ascii" && d.fields[fx].type == 'F' && d.fields[fx].size == 4 && d.fields[fy].size == 4 &&
      d.fields[fy].type == 'F' && d.fields[fz].type == 'F' && d.fields[fz].size == 4) {
    // Fast path: float32 coordinates read straight from the buffer.
    const bool fast_i = fi >= 0 && d.fields[fi].type == 'F' && d.fields[fi].size == 4;
    const bool fast_l = fl >= 0 && d.fields[fl].type == 'U' && d.fields[fl].size == 4;
    for (size_t i = 0; i < n; ++i) {
      float x, y, z, in = 0.f;
      uint32_t lb = 0;
      std::memcpy(&x, d.base[fx] + i * d.step[fx], 4);
      std::memcpy(&y, d.base[fy] + i * d.step[fy], 4);
      std::memcpy(&z, d.base[fz] + i * d.step[fz], 4);
      if (fi >= 0) {
        if (fast_i) std::memcpy(&in, d.base[fi] + i * d.step[fi], 4);
        else in = static_cast<float>(d.value(fi, i));
      }
      if (fl >= 0) {
        if (fast_l) std::memcpy(&lb, d.base[fl] + i * d.step[fl], 4);
        else lb = detail::to_label(d.value(fl, i), s);
      }
      detail::add_point(s, scan_id, uint32_t(i), x, y, z, fi >= 0, in, fl >= 0, lb);
    }
  } else {
    read_by_value(d, fx, fy, fz, fi, fl, Eigen::Isometry3d::Identity(), scan_id, s);
  }
  if (!d.viewpoint_identity) s.viewpoint = d.viewpoint;
  return s;
}

ScanFile read_kitti_bin(const std::string& path, uint32_t scan_id) {
  const std::string bytes = detail::read_whole_file(path);
  if (bytes.size() % 16 != 0)
    throw Error(path + ": KITTI .bin size " + std::to_string(bytes.size()) +
                " is not a multiple of 16 bytes (float32 x y z intensity)");
  const size_t n = bytes.size() / 16;
  ScanFile s;
  s.points_in_file = static_cast<uint32_t>(n);
  s.points.reserve(n);
  s.points.intensity.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    float v[4];
    std::memcpy(v, bytes.data() + i * 16, 16);
    detail::add_point(s, scan_id, uint32_t(i), v[0], v[1], v[2], true, v[3], false, 0);
  }
  return s;
}

}  // namespace

ScanFile read_scan(const std::string& path, uint32_t scan_id, bool map_frame) {
  const std::string ext = lower_extension(path);
  if (ext != ".pcd" && ext != ".ply" && ext != ".bin")
    throw Error(path + ": unknown scan file type '" + ext + "' (expected .pcd, .ply or .bin)");
  ScanFile s;
  try {
    s = ext == ".pcd" ? read_pcd_scan(path, scan_id, map_frame)
        : ext == ".ply" ? detail::read_ply(path, scan_id)
                        : read_kitti_bin(path, scan_id);
  } catch (const std::bad_alloc&) {
    throw Error(path + ": out of memory reading it (a header promising more points than memory holds?)");
  } catch (const std::length_error&) {
    throw Error(path + ": its header asks for more points than a vector can hold: a corrupt header");
  }
  detail::drop_bad_labels(s);
  return s;
}

}  // namespace lista::io
