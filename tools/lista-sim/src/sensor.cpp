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

}  // namespace

const std::vector<std::string>& sensor_names() {
  static const std::vector<std::string> n = {"os0-128", "xt32", "vlp16"};
  return n;
}

const std::vector<std::string>& all_sensor_names() {
  static const std::vector<std::string> n = {"os0-128", "xt32", "vlp16", "os1-64", "hdl32"};
  return n;
}

SensorModel make_sensor(const std::string& name, int columns) {
  SensorModel s;
  s.name = name;
  if (name == "os0-128") {  // Ouster OS0-128: 90 deg vertical FoV, 1024x10 mode
    s.elevations = uniform_beams(128, -45.0, 45.0);
    s.columns = 1024;
    s.min_range = 0.3;
    s.max_range = 50.0;
    s.range_sigma = 0.015;
    s.dropout = 0.005;
  } else if (name == "xt32") {  // Hesai PandarXT-32: -16..+15 deg, 1 deg spacing, 10 Hz
    s.elevations = uniform_beams(32, -16.0, 15.0);
    s.columns = 2000;
    s.min_range = 0.05;
    s.max_range = 120.0;
    s.range_sigma = 0.01;
    s.dropout = 0.002;
  } else if (name == "vlp16") {  // Velodyne VLP-16: +-15 deg, 2 deg spacing, 10 Hz
    s.elevations = uniform_beams(16, -15.0, 15.0);
    s.columns = 1800;
    s.min_range = 0.5;
    s.max_range = 100.0;
    s.range_sigma = 0.015;
    s.dropout = 0.003;
  } else if (name == "os1-64") {  // Ouster OS1-64: 42.4 deg vertical FoV, 1024x10 mode
    s.elevations = uniform_beams(64, -21.2, 21.2);
    s.columns = 1024;
    s.min_range = 0.3;
    s.max_range = 120.0;
    s.range_sigma = 0.02;
    s.dropout = 0.005;
  } else if (name == "hdl32") {  // Velodyne HDL-32E: -30.67..+10.67 deg, 1.33 deg spacing, 10 Hz
    s.elevations = uniform_beams(32, -30.67, 10.67);
    s.columns = 2170;
    s.min_range = 1.0;
    s.max_range = 100.0;
    s.range_sigma = 0.02;
    s.dropout = 0.003;
  } else {
    std::string known;
    for (const auto& n : all_sensor_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("lista-sim: unknown sensor '" + name + "' (use one of " + known + ")");
  }
  if (columns < 0) throw Error("lista-sim: sensor columns must be > 0");
  if (columns > 0) s.columns = columns;
  return s;
}

}  // namespace lista::sim
