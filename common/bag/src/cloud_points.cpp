#include <lista/error.hpp>
#include <lista_bag/cloud_points.hpp>
#include <lista_io/byte_load.hpp>
#include <lista_io/scan_fields.hpp>

#include <algorithm>
#include <cstring>

namespace lista::bag {

namespace {

size_t type_size(uint8_t t) {
  switch (t) {
    case int8: case uint8: return 1;
    case int16: case uint16: return 2;
    case int32: case uint32: case float32: return 4;
    case float64: return 8;
    default: return 0;
  }
}

template <class T>
double load(const uint8_t* p, bool swap) {
  return double(io::load_bytes<T>(p, swap));
}

double value(const uint8_t* p, uint8_t type, bool swap) {
  switch (type) {
    case int8: return double(int8_t(*p));
    case uint8: return double(*p);
    case int16: return double(load<int16_t>(p, swap));
    case uint16: return double(load<uint16_t>(p, swap));
    case int32: return double(load<int32_t>(p, swap));
    case uint32: return double(load<uint32_t>(p, swap));
    case float32: return double(load<float>(p, swap));
    default: return load<double>(p, swap);
  }
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

}  // namespace

io::ScanFile cloud_points(const Cloud& c, uint32_t scan_id, const std::string& where, std::vector<double>* point_times) {
  const PointField* axis[3] = {nullptr, nullptr, nullptr};
  const PointField* intensity = nullptr;
  const PointField* label = nullptr;
  const PointField* time = nullptr;
  size_t intensity_rank = io::kIntensityNames.size();
  for (const auto& f : c.fields) {
    const size_t size = type_size(f.datatype);
    if (size == 0) throw Error(where + ": field '" + f.name + "' has an unknown datatype " + std::to_string(f.datatype));
    if (uint64_t(f.offset) + size > c.point_step)
      throw Error(where + ": field '" + f.name + "' lies past the point's " + std::to_string(c.point_step) + " bytes");
    const std::string n = lower(f.name);
    const size_t rank = size_t(std::find(io::kIntensityNames.begin(), io::kIntensityNames.end(), n) - io::kIntensityNames.begin());
    if (n == "x" || n == "y" || n == "z") axis[n[0] - 'x'] = &f;
    else if (rank < intensity_rank) intensity = &f, intensity_rank = rank;
    else if (n == "label" && !label) label = &f;
    else if (!time && std::find(kTimeNames.begin(), kTimeNames.end(), n) != kTimeNames.end()) time = &f;
  }
  for (int k = 0; k < 3; ++k)
    if (!axis[k]) throw Error(where + ": the cloud has no '" + std::string(1, char('x' + k)) + "' field");
  for (const PointField* f : axis)
    if (f->datatype != float32 && f->datatype != float64)
      throw Error(where + ": field '" + f->name + "' is not float32 or float64");
  const uint64_t points = uint64_t(c.width) * c.height;
  if (points > 0 && (c.point_step == 0 || uint64_t(c.row_step) < uint64_t(c.width) * c.point_step ||
                     uint64_t(c.row_step) * c.height > c.data.size()))
    throw Error(where + ": " + std::to_string(c.data.size()) + " data bytes do not hold " + std::to_string(c.height) +
                " rows of " + std::to_string(c.width) + " points (point_step " + std::to_string(c.point_step) +
                ", row_step " + std::to_string(c.row_step) + ")");
  if (points > UINT32_MAX) throw Error(where + ": more than 2^32 points in one cloud");
  io::ScanFile s;
  s.points_in_file = uint32_t(points);
  s.points.reserve(size_t(points));
  const bool swap = c.is_bigendian;  // every machine LiSTA builds for is little-endian
  if (point_times) point_times->clear();
  const bool timed = point_times && time;
  const bool integer_time = time && time->datatype != float32 && time->datatype != float64;
  uint32_t index = 0;
  for (uint32_t row = 0; row < c.height; ++row)
    for (uint32_t col = 0; col < c.width; ++col, ++index) {
      const uint8_t* p = c.data.data() + size_t(row) * c.row_step + size_t(col) * c.point_step;
      const float x = float(value(p + axis[0]->offset, axis[0]->datatype, swap));
      const float y = float(value(p + axis[1]->offset, axis[1]->datatype, swap));
      const float z = float(value(p + axis[2]->offset, axis[2]->datatype, swap));
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
        ++s.skipped_nonfinite;
        continue;
      }
      s.points.xyz.emplace_back(x, y, z);
      if (intensity) s.points.intensity.push_back(float(value(p + intensity->offset, intensity->datatype, swap)));
      if (label) s.points.label.push_back(io::to_label(value(p + label->offset, label->datatype, swap), s));
      if (timed) {
        double t = value(p + time->offset, time->datatype, swap);
        if (integer_time || t > 1e15) t *= 1e-9;
        if (t > 1e6) t -= c.stamp;  // an absolute time
        point_times->push_back(t);
      }
      s.points.scan.push_back(scan_id);
      s.points.index.push_back(index);
    }
  io::drop_bad_labels(s);
  return s;
}

}  // namespace lista::bag
