// Spinning LiDAR models: beam elevations, columns, range limits and noise.
#pragma once

#include <string>
#include <vector>

namespace lista::sim {

struct SensorModel {
  std::string name;                // "os0-128", "xt32", "vlp16", "os1-64", "hdl32"
  std::vector<double> elevations;  // beam elevation angles, radians
  int columns = 1024;              // azimuth samples per revolution
  double min_range = 0.3, max_range = 50.0;
  double range_sigma = 0.01;       // Gaussian range noise, m
  double dropout = 0.003;          // probability that a valid return is lost
  size_t rays() const { return elevations.size() * size_t(columns); }
};

// Known names: all_sensor_names(). `columns` > 0 overrides the horizontal
// resolution (the sensors' lower-resolution modes). Throws lista::Error.
SensorModel make_sensor(const std::string& name, int columns = 0);

// The sensors `lista-sim views` draws from by default (and descriptor
// training saw): os0-128, xt32, vlp16. Fixed, so a seed keeps its views.
const std::vector<std::string>& sensor_names();
// Every model make_sensor knows: the three, plus os1-64 and hdl32 (sensors
// no shipped model was trained on, to check that descriptors generalise).
const std::vector<std::string>& all_sensor_names();

}  // namespace lista::sim
