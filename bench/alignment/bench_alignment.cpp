// lista-bench-alignment DATASET... : runs align.posegraph and align.icp (the
// built plugins, loaded like lista-run does) on each dataset and prints, per
// dataset and aligner, the ATE against poses_gt.txt before and after (all
// missions under ONE rigid transform, so a misplaced mission counts in full),
// each mission's ATE fitted alone (the drift that bends a map, which one rigid
// transform per mission cannot remove), the stage time
// and the stage's own metrics. Markdown table on stdout.
#include <lista/basic_context.hpp>
#include <lista/lista.hpp>
#include <lista_alignkit/trajectory_error.hpp>
#include <lista_bench/plugin_settings.hpp>
#include <lista_bench/stage_finder.hpp>
#include <lista_io/dataset.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

using namespace lista;

namespace {

struct Errors {
  double all = -1;             // m; -1 when poses_gt is missing
  std::vector<double> single;  // per mission, fitted alone
};

Errors errors_of(const MissionSet& set) {
  Errors e;
  if (const auto t = alignkit::trajectory_error(set)) e.all = t->rmse;
  for (const auto& m : set.missions) {
    MissionSet one;
    one.missions.push_back(m);
    const auto t = alignkit::trajectory_error(one);
    e.single.push_back(t ? t->rmse : -1.0);
  }
  return e;
}

std::string fmt(double v, int digits = 3) {
  if (v < 0) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", digits, v);
  return b;
}

// One line per scan: mission, scan index, estimated pose in the common frame
// and true pose (x y z qx qy qz qw each), for plotting the residual along a route.
void write_positions(const MissionSet& set, const std::string& path) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << "# mission scan est_x est_y est_z est_qx est_qy est_qz est_qw gt_x gt_y gt_z gt_qx gt_qy gt_qz gt_qw\n";
    char line[512];
    for (const auto& m : set.missions)
      for (size_t i = 0; i < m.scans.size(); ++i) {
        const Eigen::Isometry3d e = m.sensor_to_common(i);
        const Eigen::Isometry3d g = i < m.poses_gt.size() ? m.poses_gt[i] : Eigen::Isometry3d(Eigen::Matrix4d::Constant(NAN));
        out << m.name << " " << i;
        for (const Eigen::Isometry3d* t : {&e, &g}) {
          const Eigen::Quaterniond q(t->linear());
          std::snprintf(line, sizeof line, " %.5f %.5f %.5f %.7f %.7f %.7f %.7f", t->translation().x(),
                        t->translation().y(), t->translation().z(), q.x(), q.y(), q.z(), q.w());
          out << line;
        }
        out << "\n";
      }
    if (!out) throw Error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

// Top view of every mission's aligned path against the truth (after the one
// rigid fit the ATE uses), residuals drawn `gain` times longer so that
// centimetres show on a 100 m map. Written as SVG next to the positions file.
void write_residual_plot(const MissionSet& set, const std::string& path, const std::string& title) {
  const auto error = alignkit::trajectory_error(set);
  if (!error) return;
  const double gain = 50.0;
  // Per scan: true position and the aligned one with its residual magnified.
  std::vector<Eigen::Vector2d> truth, shown;
  std::vector<size_t> mission_of;
  for (size_t m = 0; m < set.missions.size(); ++m)
    for (size_t i = 0; i < set.missions[m].scans.size(); ++i) {
      const Eigen::Vector3d g = set.missions[m].poses_gt[i].translation();
      const Eigen::Vector3d a = error->fit * set.missions[m].sensor_to_common(i).translation();
      truth.push_back(g.head<2>());
      shown.push_back(g.head<2>() + gain * (a - g).head<2>());
      mission_of.push_back(m);
    }
  Eigen::Vector2d lo = truth.front(), hi = truth.front();
  for (size_t i = 0; i < truth.size(); ++i) {
    lo = lo.cwiseMin(truth[i]).cwiseMin(shown[i]);
    hi = hi.cwiseMax(truth[i]).cwiseMax(shown[i]);
  }
  const double margin = 0.03 * std::max(hi.x() - lo.x(), hi.y() - lo.y()) + 0.5;
  lo.array() -= margin;
  hi.array() += margin;
  const double scale = 900.0 / std::max(hi.x() - lo.x(), hi.y() - lo.y());
  auto px = [&](const Eigen::Vector2d& p) {  // y up in the map, down in SVG
    char b[64];
    std::snprintf(b, sizeof b, "%.1f,%.1f", (p.x() - lo.x()) * scale, (hi.y() - p.y()) * scale + 40);
    return std::string(b);
  };
  const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e"};
  std::ostringstream svg;
  const double w = (hi.x() - lo.x()) * scale, h = (hi.y() - lo.y()) * scale + 60;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << int(w) << "' height='" << int(h)
      << "' font-family='sans-serif' font-size='14'>\n<rect width='100%' height='100%' fill='white'/>\n"
      << "<text x='8' y='22'>" << title << " (residual x" << int(gain) << ")</text>\n";
  for (size_t i = 0; i < truth.size(); ++i)
    svg << "<polyline stroke='" << colours[mission_of[i] % 5] << "' stroke-width='1' stroke-opacity='0.5' points='"
        << px(truth[i]) << " " << px(shown[i]) << "'/>\n";
  for (size_t m = 0; m < set.missions.size(); ++m) {
    std::string true_path, shown_path;
    for (size_t i = 0; i < truth.size(); ++i) {
      if (mission_of[i] != m) continue;
      true_path += px(truth[i]) + " ";
      shown_path += px(shown[i]) + " ";
    }
    svg << "<polyline fill='none' stroke='#999' stroke-width='1' points='" << true_path << "'/>\n"
        << "<polyline fill='none' stroke='" << colours[m % 5] << "' stroke-width='2' points='" << shown_path << "'/>\n"
        << "<text x='" << 8 + 140 * m << "' y='" << int(h) - 8 << "' fill='" << colours[m % 5] << "'>mission "
        << set.missions[m].name << "</text>\n";
  }
  char ate[64];
  std::snprintf(ate, sizeof ate, "ATE %.3f m", error->rmse);
  svg << "<text x='" << int(w) - 130 << "' y='22'>" << ate << "</text>\n</svg>\n";
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << svg.str();
    if (!out) throw Error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"align.posegraph vs align.icp: ATE against poses_gt.txt and stage time"};
  std::vector<std::string> datasets, sets;
  std::vector<std::string> stages = {"align.posegraph", "align.icp"};
  std::vector<std::string> plugin_dirs;
  std::string positions_dir;
  int threads = 2;
  app.add_option("datasets", datasets, "dataset folders (missions with poses_gt.txt)")->required();
  app.add_option("--stages", stages, "aligners to run")->delimiter(',');
  app.add_option("--set", sets,
                 "<plugin>.<param>=<value>: a parameter other than the default, e.g. align.posegraph.scans.neighbours=0 "
                 "(repeatable; keyed by plugin name, where lista-run's --set takes a stage id)");
  app.add_option("--threads", threads, "threads per stage")->check(lista::cli::at_least(1));
  app.add_option("--plugin-dir", plugin_dirs,
                 "extra folder of plugin libraries, searched before the shipped ones (repeatable; LISTA_PLUGIN_PATH too)")
      ->allow_extra_args(false)
      ->check(CLI::ExistingDirectory);
  app.add_option("--positions", positions_dir,
                 "write DIR/<dataset>.<aligner>.txt (per scan, aligned and true pose) and .svg (top view, residuals x50)");
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench alignment")) return *code;
  try {
    std::vector<bench::Setting> settings;
    for (const auto& s : sets) settings.push_back(bench::parse_setting(s, "align.posegraph.scans.neighbours=0"));
    bench::check_compared(settings, stages);
    // Plugins found as lista-run finds them, every setting checked against
    // its plugin's declaration and every dataset folder checked before
    // anything is printed or read.
    const bench::StageFinder finder(plugin_dirs);
    std::map<std::string, Params> stage_params;
    for (const auto& name : stages) {
      const core::RegisteredStage& stage =
          finder.find(name, "missions", "missions", "an align stage", "lista-bench-alignment");
      stage_params.emplace(name, bench::params_of(name, stage.info, settings));
    }
    for (const auto& dir : datasets)
      if (!std::filesystem::is_directory(dir)) throw Error(dir + ": no such dataset folder");
    std::cout << "| dataset | aligner | ATE before (m) | ATE after (m) | per-mission ATE before -> after (m) | "
                 "stage time (s) | metrics |\n|---|---|---|---|---|---|---|\n";
    for (const auto& dir : datasets) {
      io::DatasetOptions options;
      options.threads = threads;
      const MissionSet input = io::read_dataset(dir, options);
      const Errors before = errors_of(input);
      // align.icp is also run from the true placement of each map (its first
      // pose): the best start a single rigid ICP can have, so what remains is
      // the drift that bends the maps.
      std::vector<std::pair<std::string, bool>> runs;
      for (const auto& name : stages) {
        runs.push_back({name, false});
        if (name == "align.icp" && before.all >= 0) runs.push_back({name, true});
      }
      for (const auto& [name, from_truth] : runs) {
        const core::RegisteredStage* stage = &finder.find(name);
        Params params = stage_params.at(name);
        MissionSet first = input;
        if (from_truth) {
          params.set("initial", std::string("input"));
          for (auto& m : first.missions) m.to_common = m.poses_gt.front() * m.scans.front().pose.inverse();
        }
        BasicContext ctx(name, threads, 1);
        ctx.min_level = LogLevel::info;
        Inputs in;
        in.set("missions", Data::make(first));
        const auto start = std::chrono::steady_clock::now();
        std::string result, metrics;
        Errors after;
        try {
          const Outputs out = stage->factory(params)->run(in, ctx);
          const auto& aligned = out.at("missions").as<MissionSet>();
          after = errors_of(aligned);
          if (!positions_dir.empty()) {
            const std::string stem = positions_dir + "/" + std::filesystem::path(dir).filename().string() + "." + name +
                                     (from_truth ? ".true-start" : "");
            write_positions(aligned, stem + ".txt");
            write_residual_plot(aligned, stem + ".svg",
                                std::filesystem::path(dir).filename().string() + ": " + name + (from_truth ? " (true start)" : ""));
          }
        } catch (const Error& e) {
          result = std::string("error: ") + e.what();
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::ostringstream m;
        for (const auto& [k, v] : ctx.info.metrics[name])
          if (k.rfind("ate_", 0) != 0) m << k << "=" << fmt(v, v == static_cast<long>(v) ? 0 : 3) << " ";
        std::ostringstream single;
        for (size_t i = 0; i < before.single.size(); ++i)
          single << input.missions[i].name << " " << fmt(before.single[i]) << " -> "
                 << (i < after.single.size() ? fmt(after.single[i]) : "-") << (i + 1 < before.single.size() ? ", " : "");
        std::cout << "| " << dir << " | " << name << (from_truth ? " (true start)" : "") << " | " << fmt(before.all) << " | "
                  << (result.empty() ? fmt(after.all) : result) << " | " << single.str() << " | "
                  << fmt(seconds, 1) << " | " << m.str() << "|\n"
                  << std::flush;
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "lista-bench-alignment: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
