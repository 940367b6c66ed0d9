// Runs a plan: stages in topological order, independent stages in parallel
// (up to `jobs` at a time), values freed once no later stage needs them.
#pragma once

#include <lista/context.hpp>
#include <lista_core/plan.hpp>

#include <atomic>
#include <cstdint>
#include <iosfwd>
#include <string>

namespace lista::core {

struct RunOptions {
  int jobs = 1;          // stages at once
  int threads = 0;       // total thread budget; 0 = [pipeline].threads or all cores
  std::optional<uint64_t> seed;  // overrides [pipeline].seed (default 0)
  std::string dataset, output;   // override [pipeline].dataset / output when non-empty
  std::string pipeline_file;
  bool quiet = false;            // only warnings and errors, no progress
  LogLevel min_level = LogLevel::info;
  std::ostream* log = nullptr;   // default std::cerr
  // Set (e.g. by SIGINT) to stop; nullptr = the process-wide flag of cancel.hpp.
  const std::atomic<bool>* cancel = nullptr;
};

// Returns the run's facts (timings, metrics). Throws lista::Error from a
// stage (with stage id, plugin and TOML location) or lista::Cancelled.
RunInfo execute(const Plan& plan, const RunOptions& options);

// What execute() checks of every stage's outputs: each declared port put,
// nothing undeclared, the declared type, and the contract of typed values
// (descriptors: one finite row per input object). Throws lista::Error.
// Programs that run stages themselves (lista-bench) check the same way.
void check_outputs(const StageInfo& info, const Inputs& inputs, const Outputs& outputs);

}  // namespace lista::core
