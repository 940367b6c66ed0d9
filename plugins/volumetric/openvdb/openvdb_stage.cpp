// volumetric.openvdb: the paper's volumetric differencing on OpenVDB grids,
// built for throughput (see vdb_occupancy.cpp).
#include "vdb_occupancy.hpp"

#include "volumetric_openvdb.hpp"

#include <lista/plugin.hpp>
#include <lista_raycast/change_detection.hpp>

namespace lista::volumetric {

namespace {

StageInfo openvdb_info() {
  StageInfo info;
  info.name = "volumetric.openvdb";
  info.version = "1.2.0";
  info.summary = "Volumetric change by ray-cast occupancy grids (OpenVDB), differenced between consecutive missions";
  info.doc =
      "Volumetric change by ray-cast occupancy maps, hit and miss counters in one OpenVDB grid per mission (for "
      "throughput): the same decision, dynamics and parameters as volumetric.octomap. "
      "Details: docs/volumetric.md, \"Backends\".";
  info.inputs = {{"missions", "missions", "aligned missions (scans, poses, to_common)", false}};
  info.outputs = {{"changes", "points", "changed original points per mission, common frame", false}};
  info.params = raycast::volumetric_params();
  return info;
}

class OpenVdbStage : public Stage {
 public:
  explicit OpenVdbStage(const Params& p) : config_(raycast::volumetric_config(p)) {}

  Outputs run(const Inputs& inputs, Context& ctx) override {
    const MissionSet& missions = inputs.get<MissionSet>("missions");
    raycast::check_missions(missions);
    const raycast::PairThresholds thresholds = raycast::pair_thresholds(missions, config_);
    for (const std::string& w : thresholds.warnings) ctx.warn(w);
    for (const std::string& note : thresholds.notes) ctx.info(note);
    size_t scans = 0;
    for (const auto& m : missions.missions) scans += m.scans.size();
    std::vector<raycast::MapStats> stats(missions.missions.size());
    ctx.progress().begin("ray casting", scans);
    // Maps are built in mission order and freed when no longer needed: at
    // most two at once, however many missions there are.
    raycast::ChangeStats changes;
    MissionPoints out = raycast::detect_changes_windowed(
        missions,
        [&](size_t m) {
          ctx.throw_if_cancelled();
          return build_vdb_map(missions.missions[m], config_, ctx.threads(), stats[m], &ctx.progress());
        },
        config_, ctx.threads(), &changes);
    ctx.progress().end();
    raycast::record_stats(ctx, missions, stats, changes);
    ctx.info("changed points: " + std::to_string(out.total()));
    return Outputs::of("changes", std::move(out));
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
