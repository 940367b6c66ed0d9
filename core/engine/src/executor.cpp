// Runs stages as their inputs become available, up to `jobs` at a time, one
// thread per running stage. Outputs are kept only while a later stage needs them.
#include <lista_core/cancel.hpp>
#include <lista_core/executor.hpp>
#include <lista_core/build_info.hpp>

#include "process.hpp"
#include "progress_display.hpp"
#include "run_context.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace lista::core {

namespace {

using Clock = std::chrono::steady_clock;

std::string mib(uint64_t bytes) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(0) << double(bytes) / (1024.0 * 1024.0) << " MiB";
  return os.str();
}

// The dataset as an absolute path: a report must say which folder it was
// made from, and "data/demo" means nothing away from the shell it ran in.
std::string absolute_folder(const std::string& dir) {
  if (dir.empty()) return dir;
  std::error_code ec;
  std::filesystem::path p = std::filesystem::absolute(dir, ec);
  if (ec) return dir;
  p = p.lexically_normal();
  if (p.filename().empty() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();  // "a/b/" -> "a/b"
  return p.string();
}

// The error of a failed stage, with its id, plugin and table location.
Error stage_error(const PlannedStage& s, std::exception_ptr failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const Cancelled&) {
    throw;
  } catch (const Error& e) {
    Error out = e;
    if (out.stage_id().empty()) out.in_stage(s.id, s.stage->info.name);
    if (!out.location().known()) out.at(s.where);
    return out;
  } catch (const std::bad_alloc&) {
    return Error("out of memory").in_stage(s.id, s.stage->info.name).at(s.where);
  } catch (const std::exception& e) {
    return Error(e.what()).in_stage(s.id, s.stage->info.name).at(s.where);
  } catch (...) {
    return Error("unknown exception").in_stage(s.id, s.stage->info.name).at(s.where);
  }
}

// What the report records of the run: versions, the pipeline as it ran
// (with the command line's seed, dataset and output), seed, threads, plugins.
RunInfo run_provenance(const Plan& plan, const RunOptions& options, int budget, int jobs) {
  RunInfo info;
  info.lista_version = lista_version();
  info.git_revision = git_revision();
  info.pipeline_file = options.pipeline_file.empty() ? plan.spec.file : options.pipeline_file;
  info.pipeline_resolved = plan.resolved_toml();
  info.dataset = absolute_folder(options.dataset.empty() ? plan.spec.dataset : options.dataset);
  info.output_dir = options.output.empty() ? plan.spec.output : options.output;
  info.seed = options.seed.value_or(plan.spec.seed.value_or(0));
  info.threads = budget;
  info.jobs = jobs;
  {
    std::set<std::string> seen;
    for (const auto& s : plan.stages)
      if (seen.insert(s.stage->info.name).second)
        info.plugins.push_back({s.stage->info.name, s.stage->info.version, s.stage->library});
  }
  if (options.seed || info.dataset != plan.spec.dataset || !options.output.empty()) {
    // Keep the recorded pipeline true to what ran.
    Plan copy = plan;
    copy.spec.seed = info.seed;
    copy.spec.dataset = info.dataset;
    copy.spec.output = info.output_dir;
    info.pipeline_resolved = copy.resolved_toml();
  }
  return info;
}

// Rethrows the first real failure as a stage error; a run that only saw
// cancellation (Ctrl-C noticed by several stages) throws Cancelled.
[[noreturn]] void rethrow_failure(const Plan& plan, const std::vector<std::pair<size_t, std::exception_ptr>>& failures) {
  for (const auto& [i, f] : failures) {
    try {
      std::rethrow_exception(f);
    } catch (const Cancelled&) {
      continue;
    } catch (...) {
    }
    throw stage_error(plan.stages[i], f);
  }
  throw Cancelled();
}

}  // namespace

// Checks a stage's outputs against its declaration, and the values whose
// type has a contract (descriptors: one finite row per input object) against
// it, so a broken plugin fails itself instead of a stage downstream.
void check_outputs(const StageInfo& info, const Inputs& inputs, const Outputs& outputs) {
  for (const auto& [port, value] : outputs.values()) {
    const PortSpec* spec = info.output(port);
    if (!spec) throw Error("produced output '" + port + "' that " + info.name + " does not declare");
    if (!value) throw Error("output '" + port + "' is empty");
    if (value.type() != spec->type)
      throw Error("output '" + port + "' is '" + value.type() + "' but is declared '" + spec->type + "'");
  }
  for (const auto& port : info.outputs)
    if (!outputs.has(port.name)) throw Error("declared output '" + port.name + "' was not produced");
  const ObjectSet* objects = nullptr;  // the input objects, when there is exactly one such input
  int object_inputs = 0;
  for (const auto& [port, value] : inputs.values())
    if (value && value.type() == PortTraits<ObjectSet>::name) {
      ++object_inputs;
      objects = &value.as<ObjectSet>();
    }
  for (const auto& [port, value] : outputs.values()) {
    if (value.type() != PortTraits<DescriptorSet>::name) continue;
    const auto& d = value.as<DescriptorSet>();
    const std::string why = object_inputs == 1 ? contract_problem(d, *objects) : contract_problem(d);
    if (!why.empty()) throw Error("output '" + port + "': " + why);
  }
}

RunInfo execute(const Plan& plan, const RunOptions& options) {
  std::ostream& log = options.log ? *options.log : std::cerr;
  const bool tty = options.log == nullptr && isatty(STDERR_FILENO);
  ProgressDisplay display(log, tty, options.quiet);

  RunState run;
  run.display = &display;
  run.min_level = options.quiet ? std::max(options.min_level, LogLevel::warning) : options.min_level;
  run.cancel = options.cancel ? options.cancel : &cancel_flag();

  const int hardware = std::max(1u, std::thread::hardware_concurrency());
  const int jobs = std::max(1, options.jobs);
  const int budget = options.threads > 0 ? options.threads : plan.spec.threads.value_or(hardware);
  // Stages running side by side share the thread budget.
  const int stage_threads = std::max(1, budget / jobs);

  RunInfo& info = run.info;
  info = run_provenance(plan, options, budget, jobs);

  const size_t n = plan.stages.size();
  // How many later stages still need each (stage, port) value.
  std::map<std::pair<size_t, std::string>, int> readers;
  std::map<std::string, size_t> index_of;
  for (size_t i = 0; i < n; ++i) index_of[plan.stages[i].id] = i;
  for (const auto& s : plan.stages)
    for (const auto& in : s.inputs) ++readers[{index_of.at(in.from_stage), in.from_port}];

  std::mutex mutex;
  std::condition_variable changed;
  std::map<std::pair<size_t, std::string>, Data> values;
  enum class StageState { waiting, running, done };
  std::vector<StageState> state(n, StageState::waiting);
  // The running stages, for the crash handler's last line (cancel.hpp).
  // Called with `mutex` held.
  auto publish_running = [&] {
    std::string text;
    for (size_t k = 0; k < n; ++k)
      if (state[k] == StageState::running)
        text += (text.empty() ? "" : ", ") + plan.stages[k].id + " (" + plan.stages[k].stage->info.name + ")";
    set_running_stages(text);
  };
  std::vector<std::thread> threads(n);
  std::vector<std::pair<size_t, std::exception_ptr>> failures;  // in failing order
  int running = 0;
  size_t done = 0;

  auto run_stage = [&](size_t i, Inputs inputs) {
    const PlannedStage& s = plan.stages[i];
    const auto start = Clock::now();
    Outputs outputs;
    std::exception_ptr failure;
    try {
      RunContext context(run, s.id, stage_threads);
      std::unique_ptr<Stage> stage = s.stage->factory(s.params);
      if (!stage) throw Error("the plugin's factory returned no stage");
      outputs = stage->run(inputs, context);
      check_outputs(s.stage->info, inputs, outputs);
      inputs = Inputs();  // release this stage's hold on its inputs early
      if (run.cancel->load()) throw Cancelled();
    } catch (...) {
      failure = std::current_exception();
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    const uint64_t rss = peak_rss_bytes();
    if (!failure) {
      std::lock_guard<std::mutex> lock(run.mutex);
      info.finished.push_back({s.id, s.stage->info.name, seconds, rss});
    }
    if (!failure && !options.quiet && run.min_level <= LogLevel::info) {
      std::ostringstream os;
      os << "info: " << s.id << " (" << s.stage->info.name << ") done in " << std::fixed << std::setprecision(2)
         << seconds << " s, peak RSS " << mib(rss);
      display.line(os.str());
    }
    std::lock_guard<std::mutex> lock(mutex);
    if (failure) {
      failures.emplace_back(i, failure);
    } else {
      for (const auto& [port, value] : outputs.values())
        if (readers[{i, port}] > 0) values[{i, port}] = value;  // unused outputs are dropped now
    }
    // This stage no longer needs its inputs: drop values nobody else will read.
    for (const auto& in : s.inputs) {
      const auto key = std::make_pair(index_of.at(in.from_stage), in.from_port);
      if (--readers[key] == 0) values.erase(key);
    }
    return_free_memory();
    state[i] = StageState::done;
    --running;
    ++done;
    publish_running();
    changed.notify_all();
  };

  {
    std::unique_lock<std::mutex> lock(mutex);
    while (done < n) {
      const bool stopping = !failures.empty() || run.cancel->load();
      if (!stopping) {
        for (size_t i = 0; i < n && running < jobs; ++i) {
          if (state[i] != StageState::waiting) continue;
          const auto& s = plan.stages[i];
          if (!std::all_of(s.depends_on.begin(), s.depends_on.end(),
                           [&](size_t d) { return state[d] == StageState::done; }))
            continue;
          Inputs inputs;
          for (const auto& in : s.inputs) inputs.set(in.port, values.at({index_of.at(in.from_stage), in.from_port}));
          state[i] = StageState::running;
          ++running;
          publish_running();
          if (!options.quiet && run.min_level <= LogLevel::info)
            display.line("info: " + s.id + " (" + s.stage->info.name + ") started");
          threads[i] = std::thread(run_stage, i, std::move(inputs));
        }
      }
      if (running == 0) break;  // stopping, or nothing left that can start
      // Wake up periodically to notice Ctrl-C while stages run.
      changed.wait_for(lock, std::chrono::milliseconds(100));
    }
  }
  for (auto& t : threads)
    if (t.joinable()) t.join();
  values.clear();

  if (!failures.empty()) rethrow_failure(plan, failures);
  if (run.cancel->load() || done < n) throw Cancelled();
  return info;
}

}  // namespace lista::core
