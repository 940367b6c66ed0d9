// io.report: writes report.json and changes/<mission>.pcd (data contract,
// sect. 2) with provenance, atomically, and logs a short summary.
#include "report_build.hpp"
#include "report_output.hpp"
#include "unread_scans.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>

#include <cstdio>
#include <filesystem>
#include <map>

namespace lista::io {

namespace {

struct ReportConfig {
  std::string path;
  double unread_cell = 0.1;  // m
};

const ParamTable<ReportConfig>& param_table() {
  using C = ReportConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("path", &C::path, "output folder; empty = the run's output folder (lista-run --out)");
    t.bind("unread_cell", &C::unread_cell,
           "cube edge for placing the points of scans io.missions did not read (scan_spacing) "
           "into the change: a point in a cube holding a change point is reported with it")
        .range(0.01, 1)
        .unit("m");
  });
}

class ReportStage : public Stage {
 public:
  explicit ReportStage(const Params& p) : ReportStage(param_table().read(p)) {}
  explicit ReportStage(const ReportConfig& c) : path_(c.path), unread_cell_(c.unread_cell) {}

  Outputs run(const Inputs& in, Context& ctx) override {
    const RunInfo run = ctx.run_info();
    const std::string out_dir = path_.empty() ? run.output_dir : path_;
    if (out_dir.empty()) throw Error("no output folder: set 'path' or give the run one (lista-run --out DIR)");
    // The old report stops being current now, whatever happens next.
    std::error_code ec;
    std::filesystem::remove(std::filesystem::path(out_dir) / "report.json", ec);
    const auto& missions = in.get<MissionSet>("missions");
    const auto& objects = in.get<ObjectSet>("objects");
    const Groups* groups = in.has("groups") ? &in.get<Groups>("groups") : nullptr;
    const Matches* matches = in.has("matches") ? &in.get<Matches>("matches") : nullptr;
    const MissionPoints* changes = in.has("changes") ? &in.get<MissionPoints>("changes") : nullptr;
    Built built = build_report(missions, objects, groups, matches, changes);
    const UnreadScans unread = add_unread_scans(missions, built, unread_cell_, ctx.threads());
    ctx.record("unread_scans", double(unread.scans));
    ctx.record("unread_points_changed", double(unread.points));
    if (unread.scans > 0)
      ctx.info(std::to_string(unread.points) + " points of the " + std::to_string(unread.scans) +
               " scans io.missions did not read lie in changed cells (" + std::to_string(unread_cell_).substr(0, 4) +
               " m) and are reported with them");
    for (const auto& s : run.finished) built.report.timings_s.emplace_back(s.id, s.seconds);
    built.report.extra_json = provenance_json(run, missions.origin, objects);
    for (const auto& w : built.warnings) ctx.warn(w);
    write_output(out_dir, built);
    log_summary(built, run, out_dir, ctx);
    if (!objects.dynamics.empty())
      ctx.info("dynamics " + std::to_string(objects.dynamics.size()) +
               ": moved during their own mission, not changes (report.json \"dynamics\")");
    return {};
  }

 private:
  static void log_summary(const Built& b, const RunInfo& run, const std::string& out_dir, Context& ctx) {
    std::map<std::string, int> by_status;
    int pairs = 0;
    for (const auto& o : b.report.objects) {
      ++by_status[o.status];
      if (o.match >= 0 && o.id < o.match) ++pairs;
    }
    char line[200];
    ctx.info("report written to " + out_dir + "/report.json");
    std::snprintf(line, sizeof line, "objects %zu: moved %d, removed %d, added %d; matched pairs %d",
                  b.report.objects.size(), by_status["moved"], by_status["removed"], by_status["added"], pairs);
    ctx.info(line);
    // The matches, one line each: what moved where, and how sure we are.
    std::map<int, const lista::io::ReportObject*> by_id;
    for (const auto& o : b.report.objects) by_id[o.id] = &o;
    for (const auto& o : b.report.objects) {
      if (o.match < 0 || o.id > o.match || !by_id.count(o.match)) continue;
      const auto& m = *by_id[o.match];
      std::snprintf(line, sizeof line, "  moved %d (%s) -> %d (%s): %.2f m, confidence %.2f", o.id, o.mission.c_str(),
                    m.id, m.mission.c_str(), (m.centroid - o.centroid).norm(), std::min(o.confidence, m.confidence));
      const size_t others = o.alternative_transforms.size();
      ctx.info(std::string(line) + (others ? "; pose ambiguous (" + std::to_string(others) +
                                                 (others == 1 ? " other fits" : " others fit") + " as well)"
                                           : std::string()));
    }
    for (const auto& c : b.clouds) {
      std::snprintf(line, sizeof line, "  changes/%s.pcd: %zu points", c.mission.c_str(), c.size());
      ctx.info(line);
    }
    for (const auto& s : run.finished) {
      std::snprintf(line, sizeof line, "  %-24s %-26s %9.3f s %8.0f MiB", s.id.c_str(), s.plugin.c_str(), s.seconds,
                    double(s.peak_rss_bytes) / (1024.0 * 1024.0));
      ctx.info(line);
    }
  }

  std::string path_;
  double unread_cell_;
};

StageInfo info() {
  StageInfo s;
  s.name = "io.report";
  s.version = "1.3.0";
  s.summary = "writes report.json and changes/<mission>.pcd (data contract, section 2)";
  s.doc =
      "Writes report.json, changes/<mission>.pcd (data contract, section 2) and poses/, atomically: a failure "
      "leaves no report.json. Points of scans io.missions did not read join changes/ where they fall in the "
      "change. "
      "Details: docs/formats.md, \"Output: what a run writes\".";
  s.inputs = {{"missions", "missions", "the aligned missions (names, order, alignment)"},
              {"objects", "objects", "the change objects (common frame)"},
              {"groups", "groups", "descriptor groups of the objects", true},
              {"matches", "matches", "status, partner and transform of each object", true},
              {"changes", "points", "all change points; those in no object are written with object -1", true}};
  s.params = param_table().specs();
  return s;
}

}  // namespace

}  // namespace lista::io

LISTA_STAGE_PLUGIN(lista::io::info, lista::io::ReportStage)
