// The execution plan: a pipeline checked against the registry, with every
// parameter resolved (defaults, file, --set) and the stages in topological
// order. build_plan collects every problem, not just the first.
#pragma once

#include <lista_core/pipeline.hpp>
#include <lista_core/registry.hpp>

#include <map>
#include <string>
#include <vector>

namespace lista::core {

struct PlannedStage {
  std::string id;
  const RegisteredStage* stage = nullptr;
  Params params;
  std::vector<InputBinding> inputs;  // connected input ports
  std::vector<size_t> depends_on;    // indices into Plan::stages
  int level = 0;                     // 0 = no dependency; stages of one level may run together
  SourceLocation where;
};

struct Plan {
  PipelineSpec spec;
  std::vector<PlannedStage> stages;  // topological order (file order among equals)
  int levels = 0;
  // The pipeline as it will run (defaults and overrides applied), TOML.
  std::string resolved_toml() const;
  // Human-readable plan for --dry-run.
  std::string describe() const;
};

// Validates `spec` with `overrides` applied, creating each stage whose
// parameters passed once through its factory (then dropping it) so that a
// stage refusing its parameters together fails here, before any stage runs.
// `load_errors` (plugin libraries that failed to load) are mentioned when a
// plugin is unknown.
Plan build_plan(const PipelineSpec& spec, const std::vector<Override>& overrides,
                const Registry& registry, Diagnostics& diagnostics,
                const std::vector<std::string>& load_errors = {});

}  // namespace lista::core
