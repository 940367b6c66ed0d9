// Test helper for the io.* and align.given plugins: creates a stage through
// the plugin's real LISTA_PLUGIN entry point with defaults plus overrides
// (checked against the declared ParamSpecs, as lista-run would).
#pragma once

#include <lista/lista.hpp>
#include <lista_io/test_scratch.hpp>

#include <map>
#include <memory>
#include <string>

namespace lista_plugin_detail {
const ::lista::PluginManifest* manifest();
}

namespace lista::io_test {

struct Collect : Registrar {
  std::map<std::string, std::pair<StageInfo, StageFactory>> stages;
  void add(StageInfo info, StageFactory factory) override {
    std::string name = info.name;
    stages[name] = {std::move(info), std::move(factory)};
  }
};

inline std::unique_ptr<Stage> make_stage(const std::string& name,
                                         const std::map<std::string, ParamValue>& set = {}) {
  Collect c;
  lista_plugin_detail::manifest()->register_stages(c);
  auto& [info, factory] = c.stages.at(name);
  Params p = Params::defaults(info.params);
  for (const auto& [key, value] : set) {
    const ParamSpec* spec = info.param(key);
    if (!spec) throw Error("no parameter '" + key + "'");
    const std::string why = spec->check(value);
    if (!why.empty()) throw Error(key + ": " + why);
    p.set(key, value);
  }
  return factory(p);
}

}  // namespace lista::io_test
