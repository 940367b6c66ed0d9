// LiDAR models: spinning (beam elevations x columns) and non-repetitive
// (Livox: directions drawn afresh each sweep over a field of view), with
// range limits and noise.
#pragma once

#include <string>
#include <vector>

namespace lista::sim {

struct SensorModel {
  std::string name;                // "os0-128", "xt32", "vlp16", "os1-64", "hdl32", "mid360", "avia", "tls"
  std::vector<double> elevations;  // beam elevation angles, radians (spinning)
  int columns = 1024;              // azimuth samples per revolution (spinning)
  double min_range = 0.3, max_range = 50.0;
  double range_sigma = 0.01;       // Gaussian range noise, m
  double dropout = 0.003;          // probability that a valid return is lost
  double divergence = 0.003;       // full beam divergence, rad: the footprint grows with range
  double range_dark = 20.0;        // m: a 10 % reflective surface met head-on is still seen up to here
  // Non-repetitive (rays_per_sweep > 0): no rings; each sweep's directions
  // are a low-discrepancy sequence, started afresh per sweep, spread evenly
  // over the solid angle between elevation_min and elevation_max (radians)
  // and within azimuth_fov about +x, so the pattern never repeats.
  size_t rays_per_sweep = 0;
  double elevation_min = 0.0, elevation_max = 0.0, azimuth_fov = 2.0 * 3.14159265358979323846;
  bool non_repetitive() const { return rays_per_sweep > 0; }
  size_t rays() const { return non_repetitive() ? rays_per_sweep : elevations.size() * size_t(columns); }
};

// Known names: all_sensor_names(). `columns` > 0 overrides the horizontal
// resolution (the sensors' lower-resolution modes). Throws lista::Error.
SensorModel make_sensor(const std::string& name, int columns = 0);

// The sensors `lista-sim views` draws from by default (and descriptor
// training saw): os0-128, xt32, vlp16. Fixed, so a seed keeps its views.
const std::vector<std::string>& sensor_names();
// Every model make_sensor knows: the three, plus os1-64 and hdl32 (sensors
// no shipped model was trained on, to check that descriptors generalise),
// the non-repetitive Livox mid360 and avia, and tls, a terrestrial laser
// scanner for stop-and-go stations (360 x 300 deg at 0.2 deg, 1.35 M rays).
const std::vector<std::string>& all_sensor_names();

}  // namespace lista::sim
