// lista-eval: scores a run against a dataset's ground truth, or writes the
// perfect run. Usage:
//   lista-eval --dataset D --run OUT [--json]
//   lista-eval --dataset D --truth OUT
#include "perfect_run.hpp"
#include "print.hpp"
#include "score.hpp"

#include <lista/error.hpp>
#include <lista_io/report.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/folders.hpp>
#include <lista_cli/parse.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <thread>

namespace {

// A run scored against a dataset other than the one it was made from gives
// numbers that mean nothing; say so when the report's provenance (kept in
// `extra_json` by read_report) names another folder that exists (a moved
// dataset is not flagged).
void warn_if_other_dataset(const lista::io::Report& report, const std::string& dataset) {
  namespace fs = std::filesystem;
  const nlohmann::json extra = nlohmann::json::parse(report.extra_json, nullptr, false);
  if (!extra.is_object() || !extra.contains("provenance") || !extra["provenance"].contains("dataset") ||
      !extra["provenance"]["dataset"].is_string())
    return;
  const std::string made_from = extra["provenance"]["dataset"];
  std::error_code ec;
  if (made_from.empty() || !fs::is_directory(made_from, ec) || fs::equivalent(made_from, dataset, ec)) return;
  std::cerr << "lista-eval: warning: the run was made from " << made_from << " (report.json provenance), not "
            << dataset << "; its scores against this dataset mean nothing\n";
}

// The truth's statuses follow the run's mission order (what is earlier is
// what an object was removed from). ground_truth.json lists its missions in
// recording order; a run that compared them in another order (week10 sorts
// before week2) is scored on its own terms, which are not the dataset's.
void warn_if_other_order(const lista::eval::Truth& truth, const std::vector<std::string>& compared) {
  std::vector<std::string> recorded;
  for (const auto& m : truth.gt.missions)
    if (std::find(compared.begin(), compared.end(), m) != compared.end()) recorded.push_back(m);
  if (recorded.size() != compared.size() || recorded == compared) return;
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const auto& m : v) s += (s.empty() ? "" : ", ") + m;
    return s;
  };
  std::cerr << "lista-eval: warning: the run compared the missions in the order " << join(compared)
            << ", ground_truth.json lists them as " << join(recorded)
            << "; added and removed are scored in the run's order (list the missions in the pipeline: "
               "--set <load stage>.missions=[...])\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lista-eval: score a LiSTA run against ground truth (data contract, section 3)"};
  std::string dataset, run, truth_out;
  bool json = false, objects = false;
  int threads = int(std::max(1u, std::thread::hardware_concurrency()));
  app.add_option("--dataset", dataset, "dataset folder with ground_truth.json")->required();
  auto* run_opt = app.add_option("--run", run, "run output folder (report.json, changes/)");
  auto* truth_opt = app.add_option("--truth", truth_out, "write the perfect run from ground truth into this folder");
  run_opt->excludes(truth_opt);
  app.add_flag("--json", json, "print the scores as JSON (per-object verdicts included)");
  app.add_flag("--objects", objects, "also list every truly changed object: its report, status, match and verdict");
  app.add_option("--threads", threads, "threads for reading the dataset")->check(lista::cli::at_least(1));
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-eval")) return *code;
  if (run.empty() && truth_out.empty()) {
    std::cerr << "lista-eval: error: give --run OUT (to score) or --truth OUT (to write the perfect run)\n";
    return 2;
  }
  try {
    if (!truth_out.empty()) {
      if (const std::string why = lista::cli::output_inside_dataset(dataset, truth_out, "--truth"); !why.empty()) {
        std::cerr << "lista-eval: error: " << why << "\n";
        return 2;
      }
      const lista::eval::Truth truth = lista::eval::load_truth(dataset, {}, threads);
      lista::eval::write_perfect_run(truth, truth_out);
      std::cout << "perfect run written to " << truth_out << "\n";
      return 0;
    }
    // The report decides which missions are compared.
    const std::string report_path = (std::filesystem::path(run) / "report.json").string();
    if (!std::filesystem::exists(report_path)) throw lista::Error(report_path + ": missing");
    const lista::io::Report report = lista::io::read_report(report_path);
    const lista::eval::Truth truth = lista::eval::load_truth(dataset, report.missions, threads);
    warn_if_other_dataset(report, dataset);  // a dataset that cannot be read is an error, not this warning
    warn_if_other_order(truth, report.missions);
    const lista::eval::Score score = lista::eval::score_run(truth, run);
    std::cout << (json ? lista::eval::format_json(score) : lista::eval::format_table(score, objects));
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "lista-eval: error: " << e.what() << "\n";
    return 1;
  }
}
