// filter.ground: removes ground points (per-tile RANSAC planes).
#include "ground_removal.hpp"

#include <lista/data.hpp>
#include <lista/param_table.hpp>
#include <lista/plugin.hpp>

#include <algorithm>

namespace lista::filter {
namespace {

const ParamTable<GroundConfig>& param_table() {
  using C = GroundConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("tile_size", &C::tile_size, "xy tile edge; one plane set per tile").range(0.5, 100).unit("m");
    t.bind("distance", &C::distance, "inlier distance to the ground plane").range(0.005, 1).unit("m");
    t.bind("max_slope", &C::max_slope_deg, "steepest plane taken as ground").range(0, 45).unit("deg");
    t.bind("planes_per_tile", &C::planes_per_tile, "candidate planes tried per tile").range(1, 20);
    t.bind("min_points", &C::min_points, "fewest inliers for a ground plane").range(3, 1e9);
    t.bind("footprint_cell", &C::footprint_cell, "cell of the under-the-plane test").range(0.01, 10).unit("m");
    t.bind("max_below_fraction", &C::max_below_fraction, "under-plane points per inlier allowed").range(0, 1);
    t.bind("min_area", &C::min_area, "smallest footprint (convex hull) taken as ground; 0 = any")
        .range(0, 1e4)
        .unit("m^2");
    t.bind("max_iterations", &C::max_iterations, "RANSAC iterations per plane").range(10, 100000);
  });
}

class GroundFilterStage : public Stage {
 public:
  explicit GroundFilterStage(const Params& p) : c_(param_table().read(p)) {}

  static StageInfo info() {
    StageInfo i;
    i.name = "filter.ground";
    i.version = "1.0.0";
    i.summary = "Ground removal by per-tile RANSAC plane fitting (PCL)";
    i.doc =
        "Removes the ground from each mission's change points: near-horizontal RANSAC planes per tile, whose "
        "patches count as ground only when nothing lies under them and they spread over min_area (table tops, "
        "boxes and pallets stay). "
        "Details: docs/segmentation.md, \"filter.ground\".";
    i.inputs = {{"changes", "points", "per-mission change points"}};
    i.outputs = {{"changes", "points", "the points that are not ground"}};
    i.params = param_table().specs();
    return i;
  }

  Outputs run(const Inputs& in, Context& context) override {
    const auto& changes = in.get<MissionPoints>("changes");
    MissionPoints out;
    out.missions = changes.missions;
    size_t removed = 0;
    for (const auto& s : changes.sets) {
      context.throw_if_cancelled();
      const auto ground = find_ground(s, c_, context.threads());
      std::vector<uint32_t> keep;
      keep.reserve(s.size() - ground.size());
      size_t g = 0;
      for (uint32_t i = 0; i < s.size(); ++i) {
        if (g < ground.size() && ground[g] == i) { ++g; continue; }
        keep.push_back(i);
      }
      removed += ground.size();
      out.sets.push_back(s.select(keep));
    }
    context.record("removed_points", double(removed));
    return Outputs::of("changes", std::move(out));
  }

 private:
  GroundConfig c_;
};

}  // namespace
}  // namespace lista::filter

LISTA_STAGE_PLUGIN(lista::filter::GroundFilterStage::info, lista::filter::GroundFilterStage)
