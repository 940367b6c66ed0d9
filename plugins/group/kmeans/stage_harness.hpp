// Test helper: builds a stage of the plugin linked into the test executable
// through its real LISTA_PLUGIN entry point, with default parameters plus
// overrides, so tests exercise what lista-run loads.
#pragma once

#include <lista/lista.hpp>

#include <map>
#include <memory>
#include <string>

namespace lista_plugin_detail {
const ::lista::PluginManifest* manifest();
}

namespace lista::stage_test {

class CaptureRegistrar : public Registrar {
 public:
  void add(StageInfo info, StageFactory factory) override {
    const std::string name = info.name;
    infos[name] = std::move(info);
    factories[name] = std::move(factory);
  }
  std::map<std::string, StageInfo> infos;
  std::map<std::string, StageFactory> factories;
};

inline std::unique_ptr<Stage> make_stage(const std::string& name,
                                         const std::map<std::string, ParamValue>& overrides = {}) {
  CaptureRegistrar reg;
  lista_plugin_detail::manifest()->register_stages(reg);
  const StageInfo& info = reg.infos.at(name);
  Params p = Params::defaults(info.params);
  for (const auto& [k, v] : overrides) {
    const ParamSpec* spec = info.param(k);
    if (!spec) throw Error("test: no parameter " + k);
    const std::string problem = spec->check(v);
    if (!problem.empty()) throw Error("test: " + k + ": " + problem);
    p.set(k, v);
  }
  return reg.factories.at(name)(p);
}

}  // namespace lista::stage_test
