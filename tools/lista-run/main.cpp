// lista-run: loads plugins, validates a pipeline and runs it.
// Exit codes: 0 ok, 1 pipeline or data error, 2 usage, 130 cancelled.
#include "describe.hpp"

#include <lista_core/cancel.hpp>
#include <lista_core/executor.hpp>
#include <lista_core/loader.hpp>
#include <lista_core/plan.hpp>
#include <lista_core/text.hpp>

#include <CLI/CLI.hpp>
#include <lista_cli/folders.hpp>
#include <lista_io/atomic_file.hpp>
#include <lista_cli/parse.hpp>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <unistd.h>

namespace {

constexpr int exit_ok = 0, exit_error = 1, exit_usage = 2, exit_cancelled = 130;

int fail(const std::string& message, int code = exit_error) {
  std::cerr << "lista-run: error: " << message << "\n";
  return code;
}

namespace fs = std::filesystem;

// The folders a run reads and writes, checked before the first stage so a
// typo costs a second, not a whole run. Empty when fine, else the error.
std::string dataset_problem(const std::string& dataset) {
  std::error_code ec;
  if (dataset.empty() || fs::is_directory(dataset, ec)) return {};
  if (fs::exists(dataset, ec)) return "dataset " + dataset + " is a file; give the folder that holds the missions";
  return "dataset folder " + dataset + " does not exist";
}

// With `writable`, also whether the run can write there. A folder that does
// not exist yet is not made here: the stages that write (io.report,
// report.html) make it, so a run killed before them (SIGKILL, a second
// Ctrl-C) leaves no empty folder; its nearest existing parent must take it.
std::string output_problem(const std::string& out, bool writable) {
  std::error_code ec;
  if (out.empty()) return {};
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    return "output " + out + " exists and is not a folder; choose another --out";
  if (!writable) return {};
  if (!fs::is_directory(out, ec)) {
    fs::path parent = fs::absolute(out, ec).lexically_normal();
    if (parent.filename().empty()) parent = parent.parent_path();
    do parent = parent.parent_path();
    while (!parent.empty() && parent != parent.parent_path() && !fs::exists(parent, ec));
    if (!fs::is_directory(parent, ec)) return "cannot create the output folder " + out + ": " + parent.string() + " is not a folder";
    if (::access(parent.c_str(), W_OK | X_OK) != 0)
      return "cannot create the output folder " + out + ": " + parent.string() + ": " + std::strerror(errno);
    return {};
  }
  const fs::path probe = fs::path(out) / (".lista-run-write-test-" + std::to_string(::getpid()));
  if (!std::ofstream(probe)) return "cannot write into the output folder " + out + ": " + std::strerror(errno);
  fs::remove(probe, ec);
  return {};
}

// report.json marks a complete run (data contract): one from an earlier run
// goes before this run starts, and one this run wrote goes if it then fails
// or is cancelled, so the folder never looks complete when it is not. The
// page people open, report.html, goes with it: an earlier run's page beside
// a failed rerun would be taken for the rerun's.
// A report.html is removed only when the report.html stage wrote it: its
// generator mark near the top, or (pages from before the mark) the stage's
// exact opening with its default title. A page of the user's own stays.
bool written_by_lista(const fs::path& page) {
  std::ifstream in(page, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  return head.find("<meta name=\"generator\" content=\"LiSTA report.html\">") != std::string::npos ||
         head.rfind("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>LiSTA change report</title>",
                    0) == 0;
}

void remove_report(const std::string& out, const char* why, bool quiet) {
  std::error_code ec;
  if (out.empty()) return;
  for (const char* name : {"report.json", "report.html"}) {
    const fs::path file = fs::path(out) / name;
    if (!fs::is_regular_file(file, ec)) continue;
    if (std::string(name) == "report.html" && !written_by_lista(file)) {
      static bool said = false;  // once a run: at the start and again after a failure says nothing new
      if (!quiet && !said) std::cerr << "lista-run: kept " << file.string() << " (not written by LiSTA's report.html stage)\n";
      said = true;
      continue;
    }
    fs::remove(file, ec);
    if (!quiet) std::cerr << "lista-run: removed " << file.string() << " (" << why << ")\n";
  }
}

// The folders creating `out` makes: it and its missing parents, deepest
// first; none when it exists.
std::vector<fs::path> folders_made_for(const std::string& out) {
  std::vector<fs::path> made;
  std::error_code ec;
  if (out.empty()) return made;
  fs::path p = fs::absolute(out, ec).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();  // "out/"
  while (!p.empty() && !fs::exists(p, ec) && !ec) {
    made.push_back(p);
    if (p == p.parent_path()) break;
    p = p.parent_path();
  }
  return made;
}

// The folders this run made hold nothing worth keeping when the run fails
// before writing into them: they go, deepest first, so a failed run leaves
// no empty result folder (nor the parents made for it) behind. One the
// user made, or one with files in it, stays.
void remove_made_and_empty(const std::vector<fs::path>& made, bool quiet) {
  std::error_code ec;
  size_t removed = 0;
  for (const fs::path& p : made) {
    if (!fs::is_directory(p, ec) || !fs::is_empty(p, ec) || ec || !fs::remove(p, ec)) break;
    ++removed;
  }
  if (removed && !quiet)
    std::cerr << "lista-run: removed the empty output folder " << made.front().string()
              << (removed > 1 ? " and the " + std::to_string(removed - 1) + " folder(s) made for it" : std::string())
              << "\n";
}

struct Options {
  std::string pipeline, dataset, out, describe;
  std::vector<std::string> sets, plugin_dirs;
  int jobs = 1, threads = 0;
  int64_t seed = -1;
  bool quiet = false, validate = false, dry_run = false, list_plugins = false, json = false,
       no_default_plugins = false, verbose = false;
};

// --validate promises a JSON verdict on stdout, so a usage mistake found
// after the command line parsed is one too (exit 2, a usage error).
int usage_error(const Options& o, const std::string& message) {
  if (!o.validate) return fail(message, exit_usage);
  lista::core::Diagnostics d;
  d.error({}, "", message);
  std::cout << lista_run::verdict_json(d);
  return exit_usage;
}

int run(const Options& o) {
  using namespace lista::core;
  // A --plugin-dir that is not a folder is a mistake, not an empty folder.
  for (const auto& dir : o.plugin_dirs) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(dir, ec))
      return usage_error(o, "--plugin-dir " + dir + " is a file; give the folder that holds the plugin libraries");
    if (!std::filesystem::is_directory(dir, ec)) return usage_error(o, "--plugin-dir " + dir + ": no such folder");
  }
  Registry registry;
  const LoadResult loaded = load_plugins(registry, plugin_search_path(o.plugin_dirs, !o.no_default_plugins));
  auto warn_load_errors = [&] {
    if (!o.quiet)
      for (const auto& e : loaded.errors) std::cerr << "lista-run: warning: " << e << "\n";
  };

  if (o.list_plugins) {
    std::cout << lista_run::list_plugins(registry);
    warn_load_errors();
    return exit_ok;
  }
  if (!o.describe.empty()) {
    const RegisteredStage* stage = registry.find(o.describe);
    if (!stage) {
      warn_load_errors();
      return fail("unknown plugin '" + o.describe + "'" + did_you_mean(o.describe, registry.names()) +
                  "; see lista-run --list-plugins");
    }
    if (!o.quiet)
      for (const auto& other : registry.refused(o.describe))
        std::cerr << "lista-run: warning: plugin '" << o.describe << "' is provided twice: showing " << stage->library
                  << " (found first on the plugin search path), not " << other << "\n";
    std::cout << (o.json ? lista_run::describe_json(*stage) : lista_run::describe_text(*stage));
    return exit_ok;
  }
  if (o.pipeline.empty()) return usage_error(o, "no pipeline given; usage: lista-run PIPELINE.toml (see --help)");

  // A malformed --set stops a run at once; --validate reports it in the
  // verdict with everything else it finds, and still exits 2.
  Diagnostics malformed_sets;
  std::vector<Override> overrides;
  for (const auto& s : o.sets) {
    try {
      overrides.push_back(parse_override(s));
    } catch (const lista::Error& e) {
      if (!o.validate) return fail(e.what(), exit_usage);
      malformed_sets.error({}, "", e.message());
    }
  }
  const int invalid = malformed_sets.ok() ? exit_error : exit_usage;

  Diagnostics diagnostics = malformed_sets;
  Plan plan;
  try {
    const PipelineSpec spec = parse_pipeline_file(o.pipeline, diagnostics);
    plan = build_plan(spec, overrides, registry, diagnostics, loaded.errors);
    diagnostics.sort_by_location();
  } catch (const lista::Error& e) {
    if (o.validate) {
      // A syntax error is a verdict too.
      Diagnostics d = malformed_sets;
      d.error(e.location(), "", e.message());
      std::cout << lista_run::verdict_json(d);
      return invalid;
    }
    return fail(e.what());
  }
  const std::string dataset_dir = o.dataset.empty() ? plan.spec.dataset : o.dataset;
  const std::string output_dir = o.out.empty() ? plan.spec.output : o.out;
  for (const std::string& why :
       {dataset_problem(dataset_dir), output_problem(output_dir, false), lista::cli::output_inside_dataset(dataset_dir, output_dir, "--out")})
    if (!why.empty()) diagnostics.error({}, "", why);
  if (o.validate) {
    std::cout << lista_run::verdict_json(diagnostics);
    return diagnostics.ok() ? exit_ok : invalid;
  }
  if (!o.quiet)
    for (const auto& w : diagnostics.warnings) std::cerr << "lista-run: warning: " << w.str() << "\n";
  if (!diagnostics.ok()) {
    warn_load_errors();
    for (const auto& e : diagnostics.errors) std::cerr << "lista-run: error: " << e.str() << "\n";
    return exit_error;
  }
  if (o.dry_run) {
    std::cout << plan.describe();
    return exit_ok;
  }

  const std::vector<fs::path> made_output = folders_made_for(output_dir);
  if (std::string why = output_problem(output_dir, true); !why.empty()) return fail(why);
  remove_report(output_dir, "left by an earlier run; a complete run writes its own", o.quiet);
  // Half-written files of a run killed while writing, before this run can fail.
  if (std::error_code ec; !output_dir.empty() && fs::is_directory(output_dir, ec)) lista::io::remove_dead_temps(output_dir);

  RunOptions options;
  options.jobs = o.jobs;
  options.threads = o.threads;
  if (o.seed >= 0) options.seed = static_cast<uint64_t>(o.seed);
  options.dataset = o.dataset;
  options.output = o.out;
  options.pipeline_file = o.pipeline;
  options.quiet = o.quiet;
  options.min_level = o.verbose ? lista::LogLevel::debug : lista::LogLevel::info;
  install_sigint_handler();
  install_crash_handler("lista-run");
  try {
    execute(plan, options);
  } catch (const lista::Cancelled&) {
    remove_report(output_dir, "the run was cancelled", false);
    remove_made_and_empty(made_output, o.quiet);
    std::cerr << "lista-run: cancelled\n";
    return exit_cancelled;
  } catch (const std::exception& e) {
    remove_report(output_dir, "the run did not complete", false);
    remove_made_and_empty(made_output, o.quiet);
    return fail(e.what());
  }
  return exit_ok;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lista-run: run a LiSTA change-detection pipeline"};
  Options o;
  app.add_option("pipeline", o.pipeline, "pipeline TOML file");
  app.add_option("--dataset", o.dataset, "dataset folder (overrides [pipeline].dataset)");
  app.add_option("--out", o.out, "output folder (overrides [pipeline].output)");
  // One value per flag (repeat it), so a pipeline path after it stays positional.
  app.add_option("--set", o.sets, "override a parameter: <stage>.<param>=<value> (TOML value; bare word = string)")
      ->allow_extra_args(false);
  app.add_option("-j,--jobs", o.jobs, "stages run at once")->check(CLI::Range(1, 256));
  app.add_option("--threads", o.threads, "total thread budget (default: [pipeline].threads or all cores)")
      ->check(CLI::Range(1, 4096));
  app.add_option("--seed", o.seed, "random seed (overrides [pipeline].seed)")
      ->check(CLI::Validator(
          [](std::string& v) {
            if (v.empty() || v[0] == '-') return "must be >= 0, got " + v;
            errno = 0;
            std::strtoll(v.c_str(), nullptr, 10);
            return errno == ERANGE ? "is too large (at most 9223372036854775807), got " + v : std::string();
          },
          "SEED >= 0"));
  app.add_flag("-q,--quiet", o.quiet, "warnings and errors only: no progress, no info lines");
  app.add_flag("-v,--verbose", o.verbose, "also debug messages");
  app.add_option("--plugin-dir", o.plugin_dirs,
                 "extra folder with plugin libraries (repeatable; searched after LISTA_PLUGIN_PATH, a "
                 "colon-separated list, and before lib/lista-plugins)")
      ->allow_extra_args(false);
  app.add_flag("--no-default-plugins", o.no_default_plugins,
               "do not load lib/lista-plugins next to liblista_core (test plugins in isolation)");
  app.add_flag("--validate", o.validate, "check the pipeline and print a JSON verdict");
  app.add_flag("--dry-run", o.dry_run, "print the execution plan without running it");
  app.add_flag("--list-plugins", o.list_plugins, "list the available plugins");
  app.add_option("--describe", o.describe, "describe a plugin: ports and parameters");
  app.add_flag("--json", o.json, "with --describe: JSON output");
  if (auto code = lista::cli::parse_command_line(app, argc, argv, "lista-run")) return *code;
  if (o.validate && o.dry_run) return fail("--validate and --dry-run exclude each other", exit_usage);
  if (o.json && o.describe.empty()) return fail("--json goes with --describe PLUGIN", exit_usage);
  try {
    return run(o);
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
