// Test helper for plugin suites: builds a stage of the plugin linked into the
// test executable through its real LISTA_PLUGIN entry point, with default
// parameters plus overrides checked against the declared ParamSpecs, as
// lista-run would.
#pragma once

#include <lista/lista.hpp>

#include <map>
#include <memory>
#include <string>

namespace lista_plugin_detail {
const ::lista::PluginManifest* manifest();
}

namespace lista::plugin_test {

struct CaptureRegistrar : Registrar {
  std::map<std::string, std::pair<StageInfo, StageFactory>> stages;
  void add(StageInfo info, StageFactory factory) override {
    std::string name = info.name;
    stages[name] = {std::move(info), std::move(factory)};
  }
};

// The declared StageInfo of stage `name` of the linked plugin.
inline StageInfo stage_info(const std::string& name) {
  CaptureRegistrar reg;
  lista_plugin_detail::manifest()->register_stages(reg);
  return reg.stages.at(name).first;
}

inline std::unique_ptr<Stage> make_stage(const std::string& name, const std::map<std::string, ParamValue>& set = {}) {
  CaptureRegistrar reg;
  lista_plugin_detail::manifest()->register_stages(reg);
  auto& [info, factory] = reg.stages.at(name);
  Params p = Params::defaults(info.params);
  for (const auto& [key, value] : set) {
    const ParamSpec* spec = info.param(key);
    if (!spec) throw Error("test: no parameter '" + key + "'");
    const std::string why = spec->check(value);
    if (!why.empty()) throw Error("test: " + key + ": " + why);
    p.set(key, value);
  }
  return factory(p);
}

}  // namespace lista::plugin_test
