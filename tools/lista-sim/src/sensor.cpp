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
};
const Sheet kSheets[] = {
    {"os0-128", 128, -45.0, 45.0, 1024, 0.3, 50.0, 0.015, 0.005},  // Ouster OS0-128, 1024x10 mode
    {"xt32", 32, -16.0, 15.0, 2000, 0.05, 120.0, 0.01, 0.002},     // Hesai PandarXT-32, 1 deg spacing, 10 Hz
    {"vlp16", 16, -15.0, 15.0, 1800, 0.5, 100.0, 0.015, 0.003},    // Velodyne VLP-16, 2 deg spacing, 10 Hz
    {"os1-64", 64, -21.2, 21.2, 1024, 0.3, 120.0, 0.02, 0.005},    // Ouster OS1-64, 1024x10 mode
    {"hdl32", 32, -30.67, 10.67, 2170, 1.0, 100.0, 0.02, 0.003},   // Velodyne HDL-32E, 1.33 deg spacing, 10 Hz
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
    return names;
  }();
  return n;
}

SensorModel make_sensor(const std::string& name, int columns) {
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
  if (columns < 0) throw Error("lista-sim: sensor columns must be > 0");
  if (columns > 0) s.columns = columns;
  return s;
}

}  // namespace lista::sim
