// lista-bench-descriptors: every describe.* plugin on the same object set, side
// by side in one run: per-object time (median, p95, one thread), top-1
// retrieval accuracy, mean average precision and k-means cluster purity.
//
//   lista-bench-descriptors --views <lista-sim views folder>   (held-out shapes)
//   lista-bench-descriptors --synthetic 40                     (built-in shapes)
//
// Each view is turned by a random yaw and moved by a random offset (seeded)
// before description: the views are stored in their object's frame, and a
// descriptor must not profit from that. The floor moves with the view and
// is given as the object's floor_z (the views stand on z = 0), as
// segment.complete gives it in a pipeline; --no-floor withholds it and
// --floor-error adds a measurement error to it. Top-1 is also split by
// view size, sensor, distance and which part of the object a view shows
// (breakdowns.hpp).
#include "breakdowns.hpp"

#include <lista/basic_context.hpp>
#include <lista/data.hpp>
#include <lista_bench/plugin_settings.hpp>
#include <lista_core/cancel.hpp>
#include <lista_core/executor.hpp>
#include <lista_bench/stage_finder.hpp>
#include <lista_objfeat/retrieval.hpp>
#include <lista_objfeat/views.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>
#include <unistd.h>

namespace {

using namespace lista;

struct Row {
  std::string name;    // the entry's name: the plugin's, or the one given in --plugins
  std::string plugin;
  std::string library, version;  // which build of the plugin ran (a user's may shadow a shipped one)
  // The table's first column: `mine (describe.learned)` for a renamed entry.
  std::string title() const { return name == plugin ? name : name + " (" + plugin + ")"; }
  int dim = 0;
  double median_ms = 0, p95_ms = 0;
  objfeat::RetrievalScores scores;
  double variant_top1 = 0;  // top-1 with the generator's own ids (look-alikes apart)
  objfeat::Rows values;   // one descriptor row per view
};

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5))];
}

// One object per view, at a random pose about z and a random height; its
// floor known (floor_z, off by Gaussian error of `floor_error` m) or not.
ObjectSet posed_objects(const objfeat::ViewSet& views, uint64_t seed, bool give_floor, float floor_error) {
  // Heights and floor errors from their own streams: the yaws and offsets
  // stay those of the runs before the lift, so earlier results remain
  // comparable, and an error changes nothing else.
  std::mt19937_64 rng(seed), lift_rng(seed ^ 0x6c69667400000000ull), error_rng(seed ^ 0x6572726f72000000ull);
  std::uniform_real_distribution<float> yaw(-float(M_PI), float(M_PI)), off(-30.f, 30.f), lift(-3.f, 3.f);
  std::normal_distribution<float> error(0.f, 1.f);
  ObjectSet set;
  set.missions = {"views"};
  for (size_t i = 0; i < views.views.size(); ++i) {
    Object o;
    o.id = int(i);
    o.points = views.views[i].points;
    Eigen::Matrix3f r = Eigen::AngleAxisf(yaw(rng), Eigen::Vector3f::UnitZ()).toRotationMatrix();
    Eigen::Vector3f t(off(rng), off(rng), 0.f);
    t.z() = lift(lift_rng);
    for (auto& p : o.points.xyz) p = r * p + t;
    if (give_floor) o.floor_z = t.z() + floor_error * error(error_rng);
    o.update_geometry();
    set.objects.push_back(std::move(o));
  }
  return set;
}

// One compared entry: `describe.learned`, or `mine=describe.learned` to run a
// plugin a second time under another name (other weights, other
// parameters); settings and output rows use the name.
struct Entry {
  std::string name, plugin;
};

Entry parse_entry(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos) return {text, text};
  Entry e{text.substr(0, eq), text.substr(eq + 1)};
  const bool plain = !e.name.empty() && std::all_of(e.name.begin(), e.name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (!plain || e.plugin.empty())
    throw Error("--plugins entry '" + text + "' is not <plugin> or <name>=<plugin> with a name of letters, digits, "
                "'_' and '-' (e.g. mine=describe.learned)");
  return e;
}

// A plugin's failure as one line naming it and its library, whatever it threw.
[[noreturn]] void plugin_failed(const core::RegisteredStage& s, const std::string& what) {
  throw Error(s.info.name + " (" + (s.library.empty() ? std::string("built in") : s.library) + "): " + what);
}

template <class F>
auto guarded(const core::RegisteredStage& s, F&& call) -> decltype(call()) {
  try {
    return call();
  } catch (const Error& e) {
    plugin_failed(s, e.message());
  } catch (const std::exception& e) {
    plugin_failed(s, e.what());
  } catch (...) {
    plugin_failed(s, "unknown exception");
  }
}

Row run_plugin(const std::string& name, const core::RegisteredStage& s, const ObjectSet& objects, const std::vector<int>& labels,
               const std::vector<int>& variants, const Params& params) {
  std::unique_ptr<Stage> stage = guarded(s, [&] { return s.factory(params); });
  if (!stage) plugin_failed(s, "the plugin's factory returned no stage");
  Row row;
  row.name = name;
  row.plugin = s.info.name;
  objfeat::Rows values;
  std::vector<double> ms;
  for (size_t i = 0; i < objects.objects.size(); ++i) {
    ObjectSet one;
    one.missions = objects.missions;
    one.objects = {objects.objects[i]};
    Inputs in;
    in.set(s.info.inputs.at(0).name, Data::make(std::move(one)));
    BasicContext ctx("bench", 1, 0);
    auto t0 = std::chrono::steady_clock::now();
    Outputs out = guarded(s, [&] { return stage->run(in, ctx); });
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    // The checks lista-run makes of every output, and one width for all.
    guarded(s, [&] { core::check_outputs(s.info, in, out); });
    const DescriptorSet& d = out.at(s.info.outputs.at(0).name).as<DescriptorSet>();
    if (values.rows() == 0) values.resize(long(objects.objects.size()), d.dim());
    if (d.dim() != values.cols() || d.dim() == 0)
      plugin_failed(s, "gave " + std::to_string(d.dim()) + "-d descriptors after " + std::to_string(values.cols()) +
                           "-d ones (one width for every object)");
    values.row(long(i)) = d.values.row(0);
    if (isatty(2)) std::fprintf(stderr, "\r%s: %zu/%zu", row.name.c_str(), i + 1, objects.objects.size());
  }
  if (isatty(2)) std::fprintf(stderr, "\n");
  row.dim = int(values.cols());
  row.median_ms = percentile(ms, 0.5);
  row.p95_ms = percentile(ms, 0.95);
  row.scores = objfeat::score_retrieval(values, labels, 1);
  row.variant_top1 = labels == variants ? row.scores.top1 : objfeat::score_retrieval(values, variants, 1).top1;
  row.values = values;
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Compare describe.* plugins: time per object, top-1, mAP, cluster purity"};
  std::string views_dir, json_out, rows_dir;
  std::vector<std::string> plugin_dirs;
  std::vector<std::string> plugins = {"describe.learned", "describe.esf", "describe.rift", "describe.shot"};
  std::vector<std::string> set_texts;
  int synthetic = 0, max_views = 0;
  bool all_splits = false, no_floor = false;
  double floor_error = 0.0;
  uint64_t seed = 7;
  app.add_option("--views", views_dir, "lista-sim views folder (docs/datasets.md)");
  app.add_option("--synthetic", synthetic, "use N built-in synthetic shapes (4 views each) instead");
  app.add_flag("--all-splits", all_splits, "use every view, not only held-out shapes");
  app.add_option("--max-views", max_views, "use at most this many views (first ones), 0 = all");
  app.add_option("--plugins", plugins,
                 "stages to compare; <name>=<plugin> runs a plugin again under another name (e.g. "
                 "mine=describe.learned with --set mine.weights=my.bin)")
      ->delimiter(',');
  app.add_option("--plugin-dir", plugin_dirs,
                 "extra folder of plugin libraries, searched before the shipped ones (repeatable; LISTA_PLUGIN_PATH too)")
      ->allow_extra_args(false)
      ->check(CLI::ExistingDirectory);
  app.add_option("--set", set_texts,
                 "<plugin or name>.<param>=<value>: a parameter other than the default (repeatable)");
  app.add_option("--seed", seed, "seed of the random poses");
  app.add_flag("--no-floor", no_floor, "do not give the objects their floor height (floor_z), as a pipeline without segment.complete");
  app.add_option("--floor-error", floor_error,
                 "standard deviation (m) of a Gaussian error added to each object's floor_z, as a floor "
                 "estimated from a map is off")
      ->check(CLI::Range(0.0, 1.0))->excludes("--no-floor");
  app.add_option("--json", json_out, "also write the results as JSON");
  app.add_option("--rows", rows_dir,
                 "write DIR/<plugin>.csv: per view (held-out views in index order) its label (the shape's number in "
                 "order of first appearance in index.json, every split counted), point count and descriptor");
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench descriptors")) return *code;

  try {
    std::vector<Entry> entries;
    for (const auto& text : plugins) {
      entries.push_back(parse_entry(text));
      for (size_t k = 0; k + 1 < entries.size(); ++k)
        if (entries[k].name == entries.back().name)
          throw Error("--plugins names '" + entries.back().name + "' twice: give the second one its own name, e.g. " +
                      "b=" + entries.back().plugin);
    }
    std::vector<bench::Setting> settings;
    for (const auto& t : set_texts) settings.push_back(bench::parse_setting(t, "describe.learned.samples=8"));
    std::vector<std::string> names;
    for (const Entry& e : entries) names.push_back(e.name);
    bench::check_compared(settings, names);
    objfeat::ViewSet all, train, test;
    if (!views_dir.empty()) all = objfeat::read_views(views_dir);
    else if (synthetic > 0) all = objfeat::synthetic_views(synthetic, 4, seed);
    else throw Error("give --views <folder> (lista-sim views) or --synthetic <shapes>");
    if (all_splits || views_dir.empty()) test = all;
    else objfeat::split_by_shape(all, 0.2, seed, train, test);
    if (test.views.empty())
      throw Error(views_dir + ": no held-out views (index.json split 'val' or 'test'); score every view with --all-splits");
    if (max_views > 0 && int(test.views.size()) > max_views) test.views.resize(size_t(max_views));
    if (test.views.size() < 2) throw Error("one view is nothing to retrieve: give at least two");
    std::vector<int> labels, variants;
    std::map<int, int> per_label, per_variant;
    for (const auto& v : test.views) {
      labels.push_back(v.label);
      variants.push_back(v.variant);
      ++per_label[v.label];
      ++per_variant[v.variant];
    }
    ObjectSet objects = posed_objects(test, seed, !no_floor, float(floor_error));
    std::fprintf(stderr, "%zu objects (views) of %zu shapes\n", objects.objects.size(), per_label.size());

    // Outputs that cannot be written fail now, not after minutes of runs.
    if (!json_out.empty()) {
      if (!std::ofstream(json_out + ".tmp")) throw Error("cannot write " + json_out + ".tmp: choose another --json");
      std::filesystem::remove(json_out + ".tmp");
    }
    if (!rows_dir.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(rows_dir, ec);
      if (ec) throw Error("cannot make --rows folder " + rows_dir + ": " + ec.message());
    }
    std::vector<Row> rows;
    // Every plugin loaded and every setting checked before the first one runs.
    const bench::StageFinder finder(plugin_dirs);
    struct Compared {
      const Entry* entry;
      const core::RegisteredStage* stage;
      Params params;
    };
    std::vector<Compared> stages;
    for (const Entry& entry : entries) {
      const core::RegisteredStage& stage =
          finder.find(entry.plugin, "objects", "descriptors", "a descriptor stage", "lista-bench-descriptors");
      stages.push_back({&entry, &stage, bench::params_of(entry.name, stage.info, settings)});
    }
    // A plugin that crashes is named by the crash line (lista_core/cancel.hpp).
    core::install_crash_handler("lista-bench descriptors");
    for (const Compared& c : stages) {
      core::set_running_stages(c.entry->name + " (" + c.stage->info.name + ", " + c.stage->library + ")");
      rows.push_back(run_plugin(c.entry->name, *c.stage, objects, labels, variants, c.params));
      rows.back().library = c.stage->library;
      rows.back().version = c.stage->info.version;
    }
    core::set_running_stages("");

    std::string floor_text = no_floor ? "withheld" : "given";
    if (floor_error > 0) floor_text += ", off by " + std::to_string(std::lround(floor_error * 1000)) + " mm (sigma)";
    std::printf("objects: %zu views of %zu shapes (%zu distinct meshes), random yaw, "
                "offset and height per view (seed %llu), floor %s\n\n",
                objects.objects.size(), per_label.size(), per_variant.size(), (unsigned long long)seed,
                floor_text.c_str());
    for (const auto& st : settings) std::printf("--set %s\n", st.text.c_str());
    if (!settings.empty()) std::printf("\n");
    std::printf("| plugin | dim | median ms/object | p95 ms/object | top-1 | mAP | purity | top-1, variants |\n");
    std::printf("|---|---:|---:|---:|---:|---:|---:|---:|\n");
    nlohmann::json j = nlohmann::json::array();
    for (const auto& r : rows) {
      std::printf("| %s | %d | %.3f | %.3f | %.3f | %.3f | %.3f | %.3f |\n", r.title().c_str(), r.dim, r.median_ms,
                  r.p95_ms, r.scores.top1, r.scores.map, r.scores.purity, r.variant_top1);
      j.push_back({{"name", r.name}, {"plugin", r.plugin}, {"library", r.library}, {"version", r.version}, {"dim", r.dim}, {"median_ms", r.median_ms}, {"p95_ms", r.p95_ms},
                   {"top1", r.scores.top1}, {"map", r.scores.map}, {"purity", r.scores.purity},
                   {"top1_variants", r.variant_top1}, {"objects", objects.objects.size()},
                   {"shapes", per_label.size()}, {"variants", per_variant.size()}, {"floor_given", !no_floor},
                   {"floor_error_m", floor_error}});
      for (const auto& st : settings)
        if (st.plugin == r.name) j.back()["set"].push_back(st.text);
    }
    // Where each plugin misses: top-1 by what the views are; a breakdown the
    // folder gives no data for (synthetic views have no sensor) is left out.
    for (const bench::Breakdown& b :
         {bench::by_view_size(test), bench::by_sensor(test), bench::by_distance(test), bench::by_coverage(test)}) {
      if (b.empty()) continue;
      std::printf("\n%s:\n\n| plugin |", b.title.c_str());
      for (const auto& name : b.bins) std::printf(" %s |", name.c_str());
      std::printf("\n|---|");
      for (size_t k = 0; k < b.bins.size(); ++k) std::printf("---:|");
      std::printf("\n");
      for (const auto& r : rows) {
        std::printf("| %s |", r.title().c_str());
        nlohmann::json bins = nlohmann::json::array();
        const std::vector<bench::BinScore> scores = bench::score_bins(b, r.scores.top1_hits);
        for (size_t k = 0; k < b.bins.size(); ++k) {
          const bench::BinScore& sc = scores[k];
          sc.views ? std::printf(" %.3f (%zu) |", sc.top1(), sc.views) : std::printf(" - |");
          bins.push_back({{"bin", b.bins[k]}, {"views", sc.views}, {"top1", sc.views ? nlohmann::json(sc.top1()) : nlohmann::json(nullptr)}});
        }
        std::printf("\n");
        for (auto& e : j)
          if (e["name"] == r.name) e[b.json_key] = bins;
      }
    }
    if (!json_out.empty()) {
      {
        std::ofstream out(json_out + ".tmp");
        out << j.dump(1) << "\n";
        if (!out) throw Error("cannot write " + json_out + ".tmp");
      }
      std::filesystem::rename(json_out + ".tmp", json_out);
    }
    if (!rows_dir.empty()) {
      for (const auto& r : rows) {
        const std::string path = rows_dir + "/" + r.name + ".csv";
        {
          std::ofstream out(path + ".tmp");
          out << "label,points";
          for (long c = 0; c < r.values.cols(); ++c) out << ",d" << c;
          out << "\n";
          for (long i = 0; i < r.values.rows(); ++i) {
            out << test.views[size_t(i)].label << "," << test.views[size_t(i)].points.xyz.size();
            for (long c = 0; c < r.values.cols(); ++c) out << "," << r.values(i, c);
            out << "\n";
          }
          if (!out) throw Error("cannot write " + path + ".tmp");
        }
        std::filesystem::rename(path + ".tmp", path);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lista-bench-descriptors: %s\n", e.what());
    return 1;
  }
  return 0;
}
