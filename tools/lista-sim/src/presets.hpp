// Named dataset recipes: scene, sensor, route and changes.
#pragma once

#include "layout.hpp"
#include "scenario.hpp"

#include <string>
#include <vector>

namespace lista::sim {

struct Preset {
  std::string name;
  std::string description;
  LayoutParams layout;
  ChangeParams changes;
  RouteParams route;
  std::string sensor = "os0-128";
  int columns = 0;  // 0 = the sensor's own
};

// Throws lista::Error listing the known names for an unknown one.
Preset make_preset(const std::string& name);
const std::vector<std::string>& preset_names();

}  // namespace lista::sim
