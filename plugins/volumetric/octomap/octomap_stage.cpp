// volumetric.octomap: the paper's volumetric differencing on OctoMap OcTrees
// (the reference backend; volumetric.openvdb is the fast one).
#include "octree_occupancy.hpp"

#include "volumetric_octomap.hpp"

#include <lista/plugin.hpp>
#include <lista_raycast/change_detection.hpp>

#include <cstdio>
#include <new>

namespace lista::volumetric {

namespace {

StageInfo octomap_info() {
  return raycast::volumetric_stage_info(
      "volumetric.octomap", "1.3.0",
      "Volumetric change by ray-cast occupancy grids (OctoMap), differenced between consecutive missions",
      "Volumetric change by ray-cast occupancy maps, one OctoMap OcTree per mission (the paper's backend): a "
      "point is changed when its voxel is occupied in its mission and observed free in a neighbouring one, and "
      "dynamic when its own mission saw it free too. The same decision, dynamics and parameters as "
      "volumetric.openvdb. "
      "Details: docs/volumetric.md, \"Backends\".");
}

class OctomapStage : public Stage {
 public:
  explicit OctomapStage(const Params& p) : config_(raycast::volumetric_config(p)) {}

  Outputs run(const Inputs& inputs, Context& ctx) override {
    const MissionSet& missions = inputs.get<MissionSet>("missions");
    // Each tree stops itself at its share of the memory (octree_occupancy.cpp);
    // two built side by side, or the change decision after them, can still
    // run out: said as plainly. Two missions' trees are built side by side
    // (tree insertion is serial); with more, at most two are held, each
    // built with every thread for its key rays (about 1.5x slower).
    try {
      return raycast::run_volumetric_stage(
          inputs, ctx, config_,
          [&](size_t m, int threads, raycast::MapStats& stats) {
            return build_octree_map(missions.missions[m], config_, threads, stats, &ctx.progress());
          },
          true);
    } catch (const std::bad_alloc&) {
      char text[300];
      std::snprintf(text, sizeof text,
                    "the occupancy maps outgrow the memory at resolution %g m (max_range %g m); set a coarser "
                    "resolution or a smaller max_range",
                    config_.resolution, config_.max_range);
      throw Error(text);
    }
  }

 private:
  raycast::VolumetricConfig config_;
};

}  // namespace

// For tests and the benchmark, which run the stage without the plugin loader.
StageInfo volumetric_octomap_info() { return octomap_info(); }
std::unique_ptr<Stage> make_volumetric_octomap(const Params& p) { return std::make_unique<OctomapStage>(p); }

}  // namespace lista::volumetric

LISTA_STAGE_PLUGIN(lista::volumetric::octomap_info, lista::volumetric::OctomapStage)
