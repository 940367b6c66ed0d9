#include "sensor.hpp"

#include <lista/error.hpp>

#include <cmath>

namespace lista::sim {
namespace {

std::vector<double> uniform_beams(int n, double lo_deg, double hi_deg) {
  std::vector<double> e(n);
  for (int i = 0; i < n; ++i) e[i] = (lo_deg + (hi_deg - lo_deg) * i / double(n - 1)) * M_PI / 180.0;
  return e;
}

// Datasheet values; uniform beam spacing between the lowest and highest.
struct Sheet {
  const char* name;
  int beams;
  double lowest_deg, highest_deg;
  int columns;
  double min_range, max_range, range_sigma, dropout;
  double divergence_mrad, range_dark;  // full beam divergence; range at 10 % reflectivity
};
const Sheet kSheets[] = {
    {"os0-128", 128, -45.0, 45.0, 1024, 0.3, 50.0, 0.015, 0.005, 3.1, 15.0},  // Ouster OS0-128, 1024x10 mode
    {"xt32", 32, -16.0, 15.0, 2000, 0.05, 120.0, 0.01, 0.002, 2.6, 80.0},     // Hesai PandarXT-32, 1 deg spacing, 10 Hz
    {"vlp16", 16, -15.0, 15.0, 1800, 0.5, 100.0, 0.015, 0.003, 3.0, 50.0},    // Velodyne VLP-16, 2 deg spacing, 10 Hz
    {"os1-64", 64, -21.2, 21.2, 1024, 0.3, 120.0, 0.02, 0.005, 3.1, 45.0},    // Ouster OS1-64, 1024x10 mode
    {"hdl32", 32, -30.67, 10.67, 2170, 1.0, 100.0, 0.02, 0.003, 2.8, 50.0},   // Velodyne HDL-32E, 1.33 deg spacing, 10 Hz
    // A terrestrial laser scanner on a stop-and-go station: 360 x 300 deg
    // (the mirror sweeps -60..+90 deg on either side), 0.2 deg steps,
    // 3 mm range noise, a narrow beam.
    {"tls", 751, -60.0, 90.0, 1800, 0.6, 120.0, 0.003, 0.001, 0.3, 60.0},
};

// Non-repetitive scanners: points per 100 ms sweep (10 Hz), field of view.
struct LivoxSheet {
  const char* name;
  size_t rays;
  double lowest_deg, highest_deg, azimuth_fov_deg;
  double min_range, max_range, range_sigma, dropout;
};
const LivoxSheet kLivoxSheets[] = {
    // Livox Mid-360: 200 000 points/s, 360 x 59 deg looking mostly up, 40 m
    // at 10 % reflectivity, 2 cm (1 sigma) at 10 m.
    {"mid360", 20000, -7.0, 52.0, 360.0, 0.1, 40.0, 0.02, 0.005},  // divergence and dark range below
    // Livox Avia: 240 000 points/s, 70.4 x 77.2 deg looking ahead, 1 m blind zone.
    {"avia", 24000, -38.6, 38.6, 70.4, 1.0, 190.0, 0.02, 0.003},
};

}  // namespace

const std::vector<std::string>& sensor_names() {
  static const std::vector<std::string> n = {"os0-128", "xt32", "vlp16"};
  return n;
}

const std::vector<std::string>& all_sensor_names() {
  static const std::vector<std::string> n = [] {
    std::vector<std::string> names;
    for (const Sheet& s : kSheets) names.push_back(s.name);
    for (const LivoxSheet& s : kLivoxSheets) names.push_back(s.name);
    return names;
  }();
  return n;
}

SensorModel make_sensor(const std::string& name, int columns) {
  if (columns < 0) throw Error("lista-sim: sensor columns must be > 0");
  for (const LivoxSheet& l : kLivoxSheets) {
    if (name != l.name) continue;
    if (columns > 0) throw Error("lista-sim: sensor '" + name + "' scans no columns (a non-repetitive pattern)");
    SensorModel s;
    s.name = name;
    s.rays_per_sweep = l.rays;
    s.elevation_min = l.lowest_deg * M_PI / 180.0;
    s.elevation_max = l.highest_deg * M_PI / 180.0;
    s.azimuth_fov = l.azimuth_fov_deg * M_PI / 180.0;
    s.min_range = l.min_range;
    s.max_range = l.max_range;
    s.range_sigma = l.range_sigma;
    s.dropout = l.dropout;
    s.divergence = 0.0049;  // 0.28 deg
    s.range_dark = l.max_range * 0.5;
    s.columns = 0;
    return s;
  }
  const Sheet* sheet = nullptr;
  for (const Sheet& s : kSheets)
    if (name == s.name) sheet = &s;
  if (!sheet) {
    std::string known;
    for (const auto& n : all_sensor_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("lista-sim: unknown sensor '" + name + "' (use one of " + known + ")");
  }
  SensorModel s;
  s.name = name;
  s.elevations = uniform_beams(sheet->beams, sheet->lowest_deg, sheet->highest_deg);
  s.columns = sheet->columns;
  s.min_range = sheet->min_range;
  s.max_range = sheet->max_range;
  s.range_sigma = sheet->range_sigma;
  s.dropout = sheet->dropout;
  s.divergence = sheet->divergence_mrad * 1e-3;
  s.range_dark = sheet->range_dark;
  if (columns > 0) s.columns = columns;
  return s;
}

}  // namespace lista::sim
