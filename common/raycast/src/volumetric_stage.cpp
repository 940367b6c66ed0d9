// What every volumetric stage does around its backend's maps.
#include <lista_raycast/change_detection.hpp>

#include <lista/parallel.hpp>

#include <algorithm>

namespace lista::raycast {

namespace {

// Throws lista::Error unless there are >= 2 missions, each with loaded scans.
void check_missions(const MissionSet& missions) {
  if (missions.missions.size() < 2)
    throw Error("volumetric differencing needs at least 2 missions, got " +
                std::to_string(missions.missions.size()));
  for (const Mission& m : missions.missions) {
    if (m.scans.empty()) throw Error("mission '" + m.name + "' has no scans");
    for (const Scan& s : m.scans)
      if (!s.points) throw Error("mission '" + m.name + "': scan '" + s.file + "' has no points loaded");
  }
}

// Context::record of the per-mission numbers, keys "<mission>.<what>"
// (`<m>.misfit`: between m and the next mission), and the notes and
// warnings said.
void record_stats(Context& context, const MissionSet& missions, const std::vector<MapStats>& maps,
                  const ChangeStats& changes) {
  for (size_t m = 0; m < missions.missions.size(); ++m) {
    const std::string k = missions.missions[m].name + ".";
    if (m < maps.size()) {
      context.record(k + "rays", static_cast<double>(maps[m].rays));
      context.record(k + "voxel_visits", static_cast<double>(maps[m].voxel_visits));
      context.record(k + "voxels_walked", static_cast<double>(maps[m].voxels_walked));
      context.record(k + "occupied_voxels", static_cast<double>(maps[m].occupied_voxels));
      context.record(k + "free_voxels", static_cast<double>(maps[m].free_voxels));
    }
    if (m < changes.changed_points.size()) {
      context.record(k + "changed_points", static_cast<double>(changes.changed_points[m]));
      context.record(k + "changed_voxels", static_cast<double>(changes.changed_voxels[m]));
      context.record(k + "seen_free_points", static_cast<double>(changes.seen_free_points[m]));
    }
    if (m < changes.one_look_share.size()) context.record(k + "one_look_share", changes.one_look_share[m]);
    if (m < changes.misfit.size()) context.record(k + "misfit", changes.misfit[m]);
    if (m < changes.misfit_regions.size()) context.record(k + "misfit_regions", double(changes.misfit_regions[m]));
  }
  for (const std::string& note : changes.notes) context.info(note);
  for (const std::string& warning : changes.warnings) context.warn(warning);
}

}  // namespace

StageInfo volumetric_stage_info(std::string name, std::string version, std::string summary, std::string doc) {
  StageInfo info;
  info.name = std::move(name);
  info.version = std::move(version);
  info.summary = std::move(summary);
  info.doc = std::move(doc);
  info.inputs = {{"missions", "missions", "aligned missions (scans, poses, to_common)", false}};
  info.outputs = {{"changes", "points", "changed original points per mission, common frame", false}};
  info.params = volumetric_params();
  return info;
}

Outputs run_volumetric_stage(const Inputs& inputs, Context& ctx, const VolumetricConfig& config,
                             const MapBuilder& build, bool side_by_side) {
  const MissionSet& missions = inputs.get<MissionSet>("missions");
  check_missions(missions);
  const PairThresholds thresholds = pair_thresholds(missions, config);
  for (const std::string& w : thresholds.warnings) ctx.warn(w);
  for (const std::string& note : thresholds.notes) ctx.info(note);
  size_t scans = 0;
  for (const auto& m : missions.missions) scans += m.scans.size();
  const size_t n = missions.missions.size();
  std::vector<MapStats> stats(n);
  ctx.progress().begin("ray casting", scans);
  ChangeStats changes;
  MissionPoints out;
  if (side_by_side && n == 2) {
    std::vector<std::unique_ptr<OccupancyMap>> maps(n);
    const int outer = std::max(1, std::min(ctx.threads(), static_cast<int>(n)));
    const int inner = std::max(1, ctx.threads() / outer);
    parallel_for(n, outer, [&](size_t m) {
      ctx.throw_if_cancelled();
      maps[m] = build(m, inner, stats[m]);
    });
    ctx.progress().end();
    std::vector<const OccupancyMap*> views;
    for (auto& m : maps) views.push_back(m.get());
    out = detect_changes(missions, views, config, ctx.threads(), &changes);
  } else {
    out = detect_changes_windowed(
        missions,
        [&](size_t m) {
          ctx.throw_if_cancelled();
          return build(m, ctx.threads(), stats[m]);
        },
        config, ctx.threads(), &changes);
    ctx.progress().end();
  }
  record_stats(ctx, missions, stats, changes);
  ctx.info("changed points: " + std::to_string(out.total()));
  return Outputs::of("changes", std::move(out));
}

}  // namespace lista::raycast
