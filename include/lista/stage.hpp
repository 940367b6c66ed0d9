// The stage interface. A plugin declares, for each stage it provides, a
// StageInfo (ports and parameters) and a factory; the core validates a
// pipeline against the declarations, creates each stage with its resolved
// Params and calls run() once with the inputs connected in the pipeline.
#pragma once

#include <lista/context.hpp>
#include <lista/data.hpp>
#include <lista/params.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace lista {

struct PortSpec {
  std::string name;       // e.g. "changes"
  std::string type;       // a port type name (see data.hpp), e.g. "points"
  std::string doc;
  bool optional = false;  // inputs only: may be left unconnected
};

struct StageInfo {
  std::string name;     // "<kind>.<name>", e.g. "volumetric.octomap"
  std::string version;  // plugin version, e.g. "1.0.0"
  std::string summary;  // one line
  std::string doc;      // a few lines (<= 600 chars), last: Details: docs/<page>.md, "<heading>".
  std::vector<PortSpec> inputs, outputs;
  std::vector<ParamSpec> params;
  std::vector<ParamRename> renamed;  // old names still accepted; not parameters
  std::string kind() const { return name.substr(0, name.find('.')); }
  const ParamSpec* param(const std::string& n) const;
  const ParamRename* renamed_from(const std::string& old_name) const;
  const PortSpec* input(const std::string& n) const;
  const PortSpec* output(const std::string& n) const;
  // Empty when the declaration holds together, else what is wrong, e.g.
  // "declares parameter 'bins' twice": a parameter or port named twice, a
  // default that its own type, range or choices refuse, a port of a type
  // that is not a port type (data.hpp), an old name that is still a
  // parameter or a new one that is not. The core refuses such a stage when
  // its library loads.
  std::string declaration_problem() const;
};

class Stage {
 public:
  virtual ~Stage() = default;
  // Runs once. Must put every declared output. Throw lista::Error for bad
  // input data; the core adds the stage id, plugin and TOML location.
  virtual Outputs run(const Inputs& inputs, Context& context) = 0;
};

using StageFactory = std::function<std::unique_ptr<Stage>(const Params&)>;

}  // namespace lista
