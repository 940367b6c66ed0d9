// volumetric.octomap: the paper's volumetric differencing on OctoMap OcTrees
// (the reference backend; volumetric.openvdb is the fast one).
#include "octree_occupancy.hpp"

#include "volumetric_octomap.hpp"

#include <lista/parallel.hpp>
#include <lista/plugin.hpp>
#include <lista_raycast/change_detection.hpp>

#include <algorithm>
#include <cstdio>
#include <new>

namespace lista::volumetric {

namespace {

StageInfo octomap_info() {
  StageInfo info;
  info.name = "volumetric.octomap";
  info.version = "1.2.0";
  info.summary = "Volumetric change by ray-cast occupancy grids (OctoMap), differenced between consecutive missions";
  info.doc =
      "Volumetric change by ray-cast occupancy maps, one OctoMap OcTree per mission (the paper's backend): a "
      "point is changed when its voxel is occupied in its mission and observed free in a neighbouring one, and "
      "dynamic when its own mission saw it free too. The same decision, dynamics and parameters as "
      "volumetric.openvdb. "
      "Details: docs/volumetric.md, \"Backends\".";
  info.inputs = {{"missions", "missions", "aligned missions (scans, poses, to_common)", false}};
  info.outputs = {{"changes", "points", "changed original points per mission, common frame", false}};
  info.params = raycast::volumetric_params();
  return info;
}

class OctomapStage : public Stage {
 public:
  explicit OctomapStage(const Params& p) : config_(raycast::volumetric_config(p)) {}

  Outputs run(const Inputs& inputs, Context& ctx) override {
    // Each tree stops itself at its share of the memory (octree_occupancy.cpp);
    // two built side by side, or the change decision after them, can still
    // run out: said as plainly.
    try {
      return detect(inputs, ctx);
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
  Outputs detect(const Inputs& inputs, Context& ctx) {
    const MissionSet& missions = inputs.get<MissionSet>("missions");
    raycast::check_missions(missions);
    const raycast::PairThresholds thresholds = raycast::pair_thresholds(missions, config_);
    for (const std::string& w : thresholds.warnings) ctx.warn(w);
    for (const std::string& note : thresholds.notes) ctx.info(note);
    size_t scans = 0;
    for (const auto& m : missions.missions) scans += m.scans.size();
    const size_t n = missions.missions.size();
    std::vector<raycast::MapStats> stats(n);
    ctx.progress().begin("ray casting", scans);
    raycast::ChangeStats changes;
    MissionPoints out;
    if (n <= 2) {
      // Both trees are needed at once anyway: built side by side, each on
      // a share of the threads (tree insertion itself is serial).
      std::vector<std::unique_ptr<raycast::OccupancyMap>> maps(n);
      const int outer = std::max(1, std::min(ctx.threads(), static_cast<int>(n)));
      const int inner = std::max(1, ctx.threads() / outer);
      parallel_for(n, outer, [&](size_t m) {
        ctx.throw_if_cancelled();
        maps[m] = build_octree_map(missions.missions[m], config_, inner, stats[m], &ctx.progress());
      });
      ctx.progress().end();
      std::vector<const raycast::OccupancyMap*> views;
      for (auto& m : maps) views.push_back(m.get());
      out = raycast::detect_changes(missions, views, config_, ctx.threads(), &changes);
    } else {
      // More missions: trees built in mission order and freed when no longer
      // needed, at most two at once (a tree can take gigabytes), each using
      // every thread for its key rays. About 1.5x slower than side by side.
      out = raycast::detect_changes_windowed(
          missions,
          [&](size_t m) {
            ctx.throw_if_cancelled();
            return build_octree_map(missions.missions[m], config_, ctx.threads(), stats[m], &ctx.progress());
          },
          config_, ctx.threads(), &changes);
      ctx.progress().end();
    }
    raycast::record_stats(ctx, missions, stats, changes);
    ctx.info("changed points: " + std::to_string(out.total()));
    return Outputs::of("changes", std::move(out));
  }

  raycast::VolumetricConfig config_;
};

}  // namespace

// For tests and the benchmark, which run the stage without the plugin loader.
StageInfo volumetric_octomap_info() { return octomap_info(); }
std::unique_ptr<Stage> make_volumetric_octomap(const Params& p) { return std::make_unique<OctomapStage>(p); }

}  // namespace lista::volumetric

LISTA_STAGE_PLUGIN(lista::volumetric::octomap_info, lista::volumetric::OctomapStage)
