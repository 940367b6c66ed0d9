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
  } else {
    throw Error("lista-sim: unknown sensor '" + name + "' (use os0-128, xt32 or vlp16)");
  }
  if (columns < 0) throw Error("lista-sim: sensor columns must be > 0");
  if (columns > 0) s.columns = columns;
  return s;
}

}  // namespace lista::sim
