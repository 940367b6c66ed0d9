// report.html: the change report people look at. Writes <out>/report.html
// (self-contained: inline SVG and an embedded PNG, no network) and
// <out>/changes.ply (coloured change cloud), each written atomically.
#include "change_ply.hpp"
#include "html_page.hpp"
#include "report_model.hpp"

#include <lista/lista.hpp>
#include <lista/param_table.hpp>
#include <lista_io/atomic_file.hpp>

#include <filesystem>

namespace lista::report {

namespace {

// The page's and its maps' settings side by side (PageOptions nests the
// maps'), and the stage's own.
struct HtmlReportConfig : PageOptions, TopdownOptions {
  std::string path;
  bool ply = true;
};

const ParamTable<HtmlReportConfig>& param_table();

class HtmlReportStage : public Stage {
 public:
  explicit HtmlReportStage(const Params& p) : HtmlReportStage(param_table().read(p)) {}
  explicit HtmlReportStage(const HtmlReportConfig& c) : path_(c.path), write_ply_(c.ply), options_(c) {
    options_.topdown = c;
  }

  Outputs run(const Inputs& in, Context& ctx) override {
    const RunInfo run = ctx.run_info();
    const std::string dir = path_.empty() ? run.output_dir : path_;
    if (dir.empty())
      throw Error("no output folder: set 'path' or run with --out DIR");
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw Error("cannot create output folder '" + dir + "': " + ec.message());

    const auto& missions = in.get<MissionSet>("missions");
    const auto& objects = in.get<ObjectSet>("objects");
    const Groups* groups = in.has("groups") ? &in.get<Groups>("groups") : nullptr;
    const Matches* matches = in.has("matches") ? &in.get<Matches>("matches") : nullptr;
    const DescriptorSet* descriptors = in.has("descriptors") ? &in.get<DescriptorSet>("descriptors") : nullptr;
    if (objects.missions.size() != missions.missions.size())
      throw Error("objects name " + std::to_string(objects.missions.size()) + " missions but " +
                  std::to_string(missions.missions.size()) + " missions were read");

    const ReportModel model = build_model(objects, groups, matches);
    const std::string page = render_page(missions, model, descriptors, run, options_);
    io::write_file_atomic((std::filesystem::path(dir) / "report.html").string(), page);
    if (write_ply_) io::write_file_atomic((std::filesystem::path(dir) / "changes.ply").string(), change_ply(model, missions.origin));
    ctx.info("wrote " + (std::filesystem::path(dir) / "report.html").string());
    return {};
  }

 private:
  std::string path_;
  bool write_ply_;
  PageOptions options_;
};

StageInfo info() {
  StageInfo s;
  s.name = "report.html";
  s.version = "1.1.0";
  s.summary = "Self-contained HTML change report with top-down maps, match matrix and descriptor plot";
  s.doc =
      "Writes <out>/report.html, one self-contained page (top-down change maps per mission pair, the match "
      "matrix, a 2-D descriptor plot, an object table, timings and provenance), and <out>/changes.ply. "
      "Details: docs/formats.md, \"The HTML page\".";
  s.inputs = {{"missions", "missions", "missions as aligned (static map, mission names)"},
              {"objects", "objects", "changed objects"},
              {"groups", "groups", "descriptor groups", true},
              {"matches", "matches", "statuses, matches and transforms", true},
              {"descriptors", "descriptors", "object descriptors, for the match matrix and PCA plot", true}};
  s.params = param_table().specs();
  return s;
}

const ParamTable<HtmlReportConfig>& param_table() {
  using C = HtmlReportConfig;
  return ParamTable<C>::once([](ParamTable<C>& t) {
    t.bind("path", &C::path, "output folder; empty = the run's --out folder");
    t.bind("title", &C::title, "page title");
    t.bind("pixels", &C::pixels, "longest side of each top-down map image").range(64, 8000).unit("px");
    t.bind("max_map_points", &C::max_map_points, "static map points sampled per mission pair")
        .range(1000, 1e9);
    t.bind("ply", &C::ply, "also write changes.ply");
  });
}

}  // namespace

}  // namespace lista::report

LISTA_STAGE_PLUGIN(lista::report::info, lista::report::HtmlReportStage)
