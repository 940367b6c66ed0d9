// Top-down change map of one mission pair (paper Fig. 1/4): the static map in
// grey, removed objects red, added green, moved objects in both places joined
// by an arrow, each labelled with its id. Rendered as an SVG that embeds a PNG
// raster (stb_image_write) of the map and the object points.
#pragma once

#include "report_model.hpp"

#include <lista/missions.hpp>

#include <string>

namespace lista::report {

struct TopdownOptions {
  int pixels = 1000;                  // longest image side
  size_t max_map_points = 2'000'000;  // static map points sampled per pair
};

// SVG markup for missions `a` and `b` (indices into the mission set, which
// must hold the same names as the model).
std::string render_topdown(const MissionSet& missions, const ReportModel& model, size_t a, size_t b,
                           const TopdownOptions& options);

}  // namespace lista::report
