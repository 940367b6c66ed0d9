// The pipeline file as written: [pipeline] settings and [stages.<id>] tables
// (format: docs/pipeline-format.md). Parsing checks only the TOML structure;
// plan.hpp checks it against the registered stages.
#pragma once

#include <lista/params.hpp>
#include <lista_core/diagnostic.hpp>

#include <optional>
#include <string>
#include <vector>

namespace lista::core {

struct InputBinding {
  std::string port;                   // input port of this stage
  std::string from_stage, from_port;  // "<from_stage>.<from_port>"
  SourceLocation where;
};

// RawParam::problem of an empty TOML array: its type comes from the declared
// parameter (a list parameter accepts it, any other refuses it with this text).
inline const std::string kEmptyArrayProblem = "an empty array is only a value for a list parameter";

struct RawParam {
  std::string name;
  std::optional<ParamValue> value;  // empty if the TOML value has no parameter type
  std::string problem;              // why `value` is empty
  SourceLocation where;      // the value (type and range errors)
  SourceLocation key_where;  // the key (unknown-parameter errors)
};

struct StageSpec {
  std::string id, plugin;
  SourceLocation where;         // the [stages.<id>] table
  SourceLocation plugin_where;  // the plugin = "..." value
  std::vector<InputBinding> inputs;
  std::vector<std::string> unusable_inputs;  // ports whose reference was already reported malformed
  std::vector<RawParam> params;  // in file order
};

struct PipelineSpec {
  std::string file;  // as given
  std::string name;
  std::optional<uint64_t> seed;
  std::optional<int> threads;
  std::string dataset, output;
  std::vector<StageSpec> stages;  // in file order
  const StageSpec* find(const std::string& id) const;
};

// Parses a pipeline file. A TOML syntax error or an unreadable file throws
// lista::Error with file:line:col; structural problems (a stage without
// `plugin`, an input that is not "<stage>.<port>", ...) go to `diagnostics`.
PipelineSpec parse_pipeline_file(const std::string& path, Diagnostics& diagnostics);
PipelineSpec parse_pipeline_text(const std::string& text, const std::string& file_name,
                                 Diagnostics& diagnostics);

// `--set <stage>.<param>=<value>`: the value is parsed as a TOML value; a
// bare word that is not valid TOML is taken as a string.
struct Override {
  std::string stage, param;
  std::optional<ParamValue> value;
  std::string problem;  // why value is empty
  std::string text;     // the argument as given
};
// Throws lista::Error when the argument is not of the form id.param=value.
Override parse_override(const std::string& argument);

}  // namespace lista::core
