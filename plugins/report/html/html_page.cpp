#include "html_page.hpp"

#include "charts.hpp"
#include "svg.hpp"

#include <cmath>
#include <map>

namespace lista::report {

namespace {

const char* kStyle = R"(<style>
body{font-family:system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;margin:24px;color:#222;max-width:1200px}
h1{font-size:24px;margin-bottom:4px} h2{font-size:18px;margin-top:32px;border-bottom:1px solid #ddd;padding-bottom:4px}
.summary span{display:inline-block;margin-right:18px;font-size:16px}
.removed{color:#d62728} .added{color:#2ca02c} .moved{color:#1f77b4}
table{border-collapse:collapse;font-size:13px} td,th{border:1px solid #ddd;padding:3px 8px;text-align:right}
th{background:#f4f4f4} td.text{text-align:left}
svg.topdown{width:100%;height:auto;border:1px solid #ccc;background:#fff}
.legend span{margin-right:16px}
.warnings{background:#fdecea;border:2px solid #d62728;padding:6px 12px;font-size:14px} td.low{background:#ffe9c7} .warnings ul{margin:4px 0} pre{background:#f6f6f6;padding:8px;overflow:auto;font-size:12px}
</style>)";

// One move, said once for both of its rows: from the earlier mission's
// object to the later one's, the distance between their centroids and the
// turn about z of the earlier one's transform (objects on floors turn about
// z), with the direction named ("6.47 m, 81.4° A → B").
std::string motion_text(const ObjectView& v, const ReportModel& model) {
  const ObjectView* p = v.match >= 0 ? model.find(v.match) : nullptr;
  if (!p) return "";
  const ObjectView& from = v.object->mission < p->object->mission ? v : *p;
  const ObjectView& to = &from == &v ? *p : v;
  const double moved = (to.object->centroid - from.object->centroid).cast<double>().norm();
  std::string s = fmt(moved, 2) + " m";
  auto turn = [](const Eigen::Matrix4d& T, double sign) {
    return fmt(sign * std::atan2(T(1, 0), T(0, 0)) * 180.0 / M_PI, 1) + "&deg;";
  };
  // The earlier object's transform, or the later one's inverse turn.
  const ObjectView* with = from.transform ? &from : to.transform ? &to : nullptr;
  const double sign = with == &from ? 1.0 : -1.0;
  if (with) s += ", " + turn(*with->transform, sign);
  s += " " + escape(model.missions[from.object->mission]) + " &rarr; " + escape(model.missions[to.object->mission]);
  // A symmetric shape fits as well turned: say so rather than let one
  // number look certain.
  if (with && !with->alternative_transforms.empty()) {
    s += "; pose ambiguous, also fits";
    const Eigen::Matrix4d& T = *with->transform;
    const Eigen::Vector4d c = with->object->centroid.cast<double>().homogeneous();
    for (size_t k = 0; k < with->alternative_transforms.size(); ++k) {
      const Eigen::Matrix4d& A = with->alternative_transforms[k];
      const double turn_apart = std::abs(std::remainder(std::atan2(A(1, 0), A(0, 0)) - std::atan2(T(1, 0), T(0, 0)), 2 * M_PI));
      // The same turn slid along the object (a long shelf): say the slide.
      s += (k ? ", " : " ") + (turn_apart < M_PI / 36 ? "shifted " + fmt(((A - T) * c).norm(), 2) + " m"
                                                    : turn(A, sign));
    }
  }
  return s;
}


// With 3+ missions `match` names one partner; the chain of the object's
// reports ("5 A → 8 B → 19 C") shows where it was in every mission.
std::string history_text(const ObjectView& v, const ReportModel& model) {
  if (v.history.size() < 2) return "";
  std::string s;
  for (int id : v.history) {
    const ObjectView* o = model.find(id);
    s += (s.empty() ? "" : " &rarr; ") + std::to_string(id) +
         (o ? " " + escape(model.missions[o->object->mission]) : std::string());
  }
  return s;
}

// "circle A, square B, triangle C" (charts.cpp's mission_marker shapes).
std::string marker_legend(const std::vector<std::string>& missions) {
  static const char* shapes[] = {"circle", "square", "triangle", "diamond"};
  std::string s;
  for (size_t m = 0; m < missions.size(); ++m) s += (m ? ", " : "") + std::string(shapes[m % 4]) + " " + escape(missions[m]);
  return s;
}

std::string vec(const Eigen::Vector3d& p) {
  return fmt(p.x()) + ", " + fmt(p.y()) + ", " + fmt(p.z());
}

}  // namespace

std::string render_page(const MissionSet& missions, const ReportModel& model,
                        const DescriptorSet* descriptors, const RunInfo& run, const PageOptions& options) {
  std::map<std::string, int> counts;
  int moves = 0;  // pairs of reports: each move has a report at both ends
  int still = 0;  // reports of an object where it stood still before or after its change (history.static)
  for (const auto& v : model.objects) {
    if (v.object->points.has_changed_against() && v.object->points.changed_against_all() == 0) {
      ++still;
      continue;
    }
    ++counts[to_string(v.status)];
    if (v.status == ChangeStatus::moved && v.match >= 0 && v.object->id < v.match) ++moves;
  }

  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">" + std::string(kGeneratorMeta) + "<title>" +
                     escape(options.title) + "</title>" + kStyle + "</head>\n<body>\n";
  html += "<h1>" + escape(options.title) + "</h1>\n<p>Missions: ";
  for (size_t m = 0; m < model.missions.size(); ++m)
    html += (m ? " &rarr; " : "") + escape(model.missions[m]);
  html += "</p>\n";
  // What went wrong on the way (a failed alignment, say) comes before any
  // finding it may have spoilt, not in a log that scrolled away.
  if (!run.warnings.empty()) {
    html += "<div class=\"warnings\"><b>Warnings during the run (" + std::to_string(run.warnings.size()) +
            "): read them before the findings below</b><ul>\n";
    for (const auto& w : run.warnings) html += "<li>" + escape(w) + "</li>\n";
    html += "</ul></div>\n";
  }
  html += "<p class=\"summary\"><span class=\"removed\">removed: " + std::to_string(counts["removed"]) +
          "</span><span class=\"added\">added: " + std::to_string(counts["added"]) +
          "</span><span class=\"moved\">moved: " + std::to_string(moves) + (moves == 1 ? " move (" : " moves (") + std::to_string(counts["moved"]) +
          " reports at their ends)</span>" +
          (still ? "<span>standing still before or after their change: " + std::to_string(still) + "</span>"
                 : std::string()) +
          "<span>objects: " + std::to_string(model.objects.size()) + "</span>" +
          (model.dynamics.empty() ? std::string()
                                  : "<span class=\"dynamic\">moved during their own mission (dynamic, not changes; "
                                    "dotted grey on the maps): " +
                                        std::to_string(model.dynamics.size()) + "</span>") +
          "</p>\n";
  // Contents: with many missions the page runs to thousands of pixels.
  html += "<p class=\"contents\">Contents: ";
  for (size_t a = 0; a + 1 < model.missions.size(); ++a)
    html += "<a href=\"#map-" + std::to_string(a) + "\">" + escape(model.missions[a]) + " &rarr; " +
            escape(model.missions[a + 1]) + "</a> &middot; ";
  html += "<a href=\"#objects\">objects</a> &middot; <a href=\"#stages\">stages</a> &middot; "
          "<a href=\"#provenance\">provenance</a></p>\n";

  for (size_t a = 0; a + 1 < model.missions.size(); ++a) {
    const size_t b = a + 1;
    html += "<h2 id=\"map-" + std::to_string(a) + "\">Change map: " + escape(model.missions[a]) + " &rarr; " + escape(model.missions[b]) + "</h2>\n";
    html += "<p class=\"legend\"><span class=\"removed\">&#9632; removed</span><span class=\"added\">&#9632; added"
            "</span><span class=\"moved\">&#9632; moved (arrow: from " + escape(model.missions[a]) + " to " +
            escape(model.missions[b]) + "; points drawn darker in " + escape(model.missions[b]) +
            ")</span><span>dashed box: confidence below " + fmt(kLowConfidence, 1) +
            "</span><span>grey: static map</span></p>\n";
    if (model.missions.size() > 2)
      html += "<p class=\"legend\">Colours say what each object did between these two missions; the table's "
              "status is the object's one report status, which may name its change against its other "
              "neighbouring mission (see its history).</p>\n";
    html += render_topdown(missions, model, a, b, options.topdown);
    html += "<h2>Match matrix: " + escape(model.missions[a]) + " &times; " + escape(model.missions[b]) + "</h2>\n";
    html += "<p>Cell colour: object similarity (" +
            std::string(descriptors ? "descriptor" : "physical") +
            " distance, min-max normalised; darker = more alike" +
            std::string(descriptors ? "; pale grey: an object without a descriptor, found after the describe stage" : "") +
            "). Outlined: reported match with its confidence.</p>\n";
    html += render_match_matrix(model, descriptors, a, b);
  }

  if (descriptors) {
    const std::string pca = render_pca(model, *descriptors);
    if (!pca.empty()) {
      html += "<h2>Descriptors (" + escape(descriptors->method) + ", " + std::to_string(descriptors->dim()) +
              "-d) by PCA</h2>\n<p>Colour: group; shape: mission (" + marker_legend(model.missions) + ").</p>\n" + pca;
    }
  }

  html += "<h2 id=\"objects\">Objects</h2>\n<p>Highlighted confidence: below " + fmt(kLowConfidence, 1) +
          ". Motion: one move said once for both of its reports, earlier mission first.</p>\n"
          "<table class=\"objects\"><tr><th>id</th><th>mission</th><th>status</th><th>group</th>"
          "<th>confidence</th><th>match</th><th>centroid (m)</th><th>points</th><th>motion</th><th>history</th></tr>\n";
  for (const auto& v : model.objects) {
    const std::string status = to_string(v.status);
    html += "<tr class=\"object-row\" data-id=\"" + std::to_string(v.object->id) + "\"><td>" +
            std::to_string(v.object->id) + "</td><td class=\"text\">" + escape(model.missions[v.object->mission]) +
            "</td><td class=\"text " + status + "\">" + status + "</td><td>" +
            (v.group >= 0 ? std::to_string(v.group) : "") + "</td><td" +
            (v.confidence < kLowConfidence ? " class=\"low\"" : "") + ">" + fmt(v.confidence) + "</td><td>" +
            (v.match >= 0 ? std::to_string(v.match) : "") + "</td><td>" + vec(v.object->centroid.cast<double>() + missions.origin) + "</td><td>" +
            std::to_string(v.object->points.size()) + "</td><td>" + motion_text(v, model) + "</td><td class=\"text\">" +
            history_text(v, model) + "</td></tr>\n";
  }
  html += "</table>\n";

  html += "<h2 id=\"stages\">Stages</h2>\n<table class=\"timings\"><tr><th>stage</th><th>plugin</th><th>time (s)</th>"
          "<th>peak memory (MiB)</th></tr>\n";
  for (const auto& s : run.finished)
    html += "<tr><td class=\"text\">" + escape(s.id) + "</td><td class=\"text\">" + escape(s.plugin) + "</td><td>" +
            fmt(s.seconds, 3) + "</td><td>" + fmt(s.peak_rss_bytes / 1048576.0, 0) + "</td></tr>\n";
  html += "</table>\n<h2 id=\"provenance\">Provenance</h2>\n<table class=\"provenance\">";
  auto row = [&](const std::string& k, const std::string& v) {
    html += "<tr><th>" + escape(k) + "</th><td class=\"text\">" + escape(v) + "</td></tr>";
  };
  row("LiSTA", run.lista_version);
  row("git revision", run.git_revision);
  row("pipeline", run.pipeline_file);
  row("dataset", run.dataset);
  // Georeferenced data: maps and changes.ply are drawn around this point.
  if (!missions.origin.isZero())
    row("local frame origin", vec(missions.origin) + " (maps and changes.ply: add it for the dataset's coordinates)");
  row("seed", std::to_string(run.seed));
  row("threads", std::to_string(run.threads));
  row("stages at once (-j)", std::to_string(run.jobs));
  for (const auto& p : run.plugins) row("plugin " + p.name, p.version + " (" + p.library + ")");
  // What stages noted about their inputs (describe.learned: its weights file and SHA-256).
  for (const auto& [stage, notes] : run.notes)
    for (const auto& [key, text] : notes) row(stage + " " + key, text);
  html += "</table>\n";
  if (!run.pipeline_resolved.empty())
    html += "<details><summary>Resolved pipeline</summary><pre>" + escape(run.pipeline_resolved) + "</pre></details>\n";
  // Marks a complete render: tests read these attributes from the DOM.
  html += "<script>document.body.dataset.objects=document.querySelectorAll('tr.object-row').length;"
          "document.body.dataset.rendered='ok';</script>\n</body></html>\n";
  return html;
}

}  // namespace lista::report
