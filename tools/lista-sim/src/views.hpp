// `lista-sim views`: partial scans of single objects from random viewpoints
// and sensors, for training and benchmarking descriptors (docs/datasets.md).
#pragma once

#include "shapes.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace lista::sim {

struct ViewsOptions {
  std::string out;
  int objects = 100;          // object instances
  int views_per_object = 8;
  // Sweeps merged into one view, taken 1 m apart along a straight pass by the
  // object (as a robot walking past it builds its map). 1: one sweep.
  int scans_per_view = 1;
  uint64_t seed = 1;
  // Sensors each view draws from (sensor.hpp); empty: sensor_names(). The
  // draw takes the same random numbers whatever the list, so one seed gives
  // the same shapes and viewpoints with other sensors.
  std::vector<std::string> sensors;
  int threads = 1;
  bool overwrite = false;
  bool progress = false;
  // Shapes whose surfaces lie within this distance (metres, symmetric
  // Hausdorff) share one id, the label descriptors are scored and trained on
  // (look_alikes.hpp). 2 cm: above the simulated range noise (1-1.5 cm), so a
  // merged pair differs by less than a sweep resolves; the distinct mesh's id
  // stays in each view's "variant".
  double look_alike_tolerance = 0.02;
  bool procedural = true;            // draw from the procedural classes too
  std::vector<Shape> extra_shapes;  // sweethome3d meshes (furniture.hpp), if loaded
};

struct ViewsStats {
  size_t views = 0, shapes = 0, points = 0;
};

ViewsStats write_views(const ViewsOptions& options);

}  // namespace lista::sim
