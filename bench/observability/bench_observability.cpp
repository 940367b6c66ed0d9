// lista-bench observability --dataset DIR: how much of a dataset's true
// change the missions' scans could show at all. Each truly changed point
// (ground_truth.json, data contract sect. 3) is looked up, at the true
// poses, in the scans of the neighbouring missions it changed against: seen
// empty there (a ray passed it), something there, or not seen. The share
// seen empty bounds the recall of the change evidence; the share in objects
// with some evidence (--min-evidence points seen empty) bounds the recall of
// a pipeline that completes each object from its evidence
// (docs/benchmarks.md, "Observability").
#include "observability.hpp"

#include <lista/error.hpp>
#include <lista_io/dataset.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/parse.hpp>

#include <cstdio>
#include <filesystem>

int main(int argc, char** argv) {
  CLI::App app{"the share of the true change the other missions' scans saw at all (a recall ceiling)"};
  std::string dataset;
  ObservabilityOptions o;
  app.add_option("--dataset", dataset, "dataset folder (data contract) with ground_truth.json and poses_gt.txt")
      ->required();
  app.add_option("--rho", o.rho, "m: a ray or a return this close to a point counts for it (half the diff voxel)")
      ->check(lista::cli::between(0.001, 1.0));
  app.add_option("--margin", o.margin, "m: a ray must end this far beyond a point to have passed it")
      ->check(lista::cli::between(0.0, 10.0));
  app.add_option("--min-evidence", o.min_evidence, "points seen empty that make an object's change visible")
      ->check(CLI::Range(1, 1000000));
  bool objects = false;
  app.add_flag("--objects", objects, "also a row per changed object");
  app.add_option("--threads", o.threads, "threads")->check(CLI::Range(1, 256));
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-bench observability")) return *code;
  try {
    const std::filesystem::path truth_file = std::filesystem::path(dataset) / "ground_truth.json";
    if (!std::filesystem::exists(truth_file))
      throw lista::Error(truth_file.string() + ": not found; the benchmark scores against the dataset's truth");
    const lista::io::GroundTruth truth = lista::io::read_ground_truth(truth_file.string());
    lista::io::DatasetOptions read;
    read.threads = o.threads;
    const lista::MissionSet missions = lista::io::read_dataset(dataset, read);
    const auto rows = observability(missions, truth, o);
    std::printf("%s: rho %.3f m, margin %.3f m\n", dataset.c_str(), o.rho, o.margin);
    std::printf("%-12s %12s %12s %12s %12s %16s\n", "mission", "changed pts", "seen empty", "something", "not seen",
                "in seen objects");
    uint64_t changed = 0, empty = 0, visible = 0;
    for (const auto& r : rows) {
      auto pct = [&](uint64_t n) { return r.changed ? 100.0 * double(n) / double(r.changed) : 0.0; };
      std::printf("%-12s %12llu %11.1f%% %11.1f%% %11.1f%% %15.1f%%\n", r.mission.c_str(),
                  (unsigned long long)r.changed, pct(r.seen_empty), pct(r.seen_present),
                  pct(r.changed - r.seen_empty - r.seen_present), pct(r.in_visible_objects));
      if (objects)
        for (const auto& b : r.objects) {
          std::string name = std::to_string(b.id);
          for (const auto& t : truth.objects)
            if (uint32_t(t.id) == b.id) name += " " + t.class_name;
          auto opct = [&](uint64_t n) { return 100.0 * double(n) / double(b.changed); };
          std::printf("  %-18s %8llu %11.1f%% %11.1f%% %11.1f%%\n", name.c_str(), (unsigned long long)b.changed,
                      opct(b.seen_empty), opct(b.seen_present), opct(b.changed - b.seen_empty - b.seen_present));
        }
      changed += r.changed;
      empty += r.seen_empty;
      visible += r.in_visible_objects;
    }
    auto share = [&](uint64_t n) { return changed ? double(n) / double(changed) : 0.0; };
    auto f1 = [](double recall) { return recall > 0 ? 2 * recall / (1 + recall) : 0.0; };
    std::printf("recall ceiling: evidence %.3f, completed objects %.3f; F1 ceiling (precision 1): %.3f, %.3f\n",
                share(empty), share(visible), f1(share(empty)), f1(share(visible)));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "lista-bench observability: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
