// volumetric.openvdb: the paper's volumetric differencing on OpenVDB grids,
// built for throughput (see vdb_occupancy.cpp).
#include "vdb_occupancy.hpp"

#include "volumetric_openvdb.hpp"

#include <lista/plugin.hpp>
#include <lista_raycast/change_detection.hpp>

namespace lista::volumetric {

namespace {

StageInfo openvdb_info() {
  return raycast::volumetric_stage_info(
      "volumetric.openvdb", "1.3.0",
      "Volumetric change by ray-cast occupancy grids (OpenVDB), differenced between consecutive missions",
      "Volumetric change by ray-cast occupancy maps, hit and miss counters in one OpenVDB grid per mission (for "
      "throughput): the same decision, dynamics and parameters as volumetric.octomap. "
      "Details: docs/volumetric.md, \"Backends\".");
}

class OpenVdbStage : public Stage {
 public:
  explicit OpenVdbStage(const Params& p) : config_(raycast::volumetric_config(p)) {}

  Outputs run(const Inputs& inputs, Context& ctx) override {
    const MissionSet& missions = inputs.get<MissionSet>("missions");
    return raycast::run_volumetric_stage(
        inputs, ctx, config_,
        [&](size_t m, int threads, raycast::MapStats& stats) {
          return build_vdb_map(missions.missions[m], config_, threads, stats, &ctx.progress());
        },
        false);
  }

 private:
  raycast::VolumetricConfig config_;
};

}  // namespace

// For tests and the benchmark, which run the stage without the plugin loader.
StageInfo volumetric_openvdb_info() { return openvdb_info(); }
std::unique_ptr<Stage> make_volumetric_openvdb(const Params& p) { return std::make_unique<OpenVdbStage>(p); }

}  // namespace lista::volumetric

LISTA_STAGE_PLUGIN(lista::volumetric::openvdb_info, lista::volumetric::OpenVdbStage)
