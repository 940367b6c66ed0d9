// Writing a plugin: one shared library, one exported entry point.
//
//   static void register_stages(lista::Registrar& r) {
//     r.add(MyStage::info(), lista::factory_of<MyStage>());
//   }
//   LISTA_PLUGIN(register_stages)
//
// or, for a plugin of one stage, LISTA_STAGE_PLUGIN(my::MyStage::info, my::MyStage).
//
// The core loads the library with RTLD_NOW, reads the manifest through the
// Boost.DLL alias `lista_plugin_manifest`, refuses it if the SDK version or
// build fingerprint differ from its own, then calls register_stages.
// Libraries are never unloaded.
#pragma once

#include <lista/stage.hpp>
#include <lista/version.hpp>

#include <boost/dll/alias.hpp>
#include <cstdint>

namespace lista {

class Registrar {
 public:
  virtual ~Registrar() = default;
  virtual void add(StageInfo info, StageFactory factory) = 0;
};

// Makes a stage class from its parameters.
template <class S>
StageFactory factory_of() {
  return [](const Params& p) -> std::unique_ptr<Stage> { return std::make_unique<S>(p); };
}

// Plain layout so the core can read the version before touching C++ types.
struct PluginManifest {
  uint32_t sdk_version;
  const char* build_fingerprint;
  void (*register_stages)(Registrar&);
};

}  // namespace lista

// Declared here so a plugin's own tests, linked against the plugin library,
// can reach its manifest: lista_plugin_detail::manifest()->register_stages(r).
namespace lista_plugin_detail {
const ::lista::PluginManifest* manifest();
}

#define LISTA_PLUGIN(register_fn)                                                       \
  namespace lista_plugin_detail {                                                        \
  const ::lista::PluginManifest* manifest() {                                            \
    static const ::lista::PluginManifest m{LISTA_SDK_VERSION, LISTA_BUILD_FINGERPRINT,   \
                                           &register_fn};                                \
    return &m;                                                                           \
  }                                                                                      \
  }                                                                                      \
  BOOST_DLL_ALIAS(lista_plugin_detail::manifest, lista_plugin_manifest)

// A plugin of one stage: its StageInfo function and its class, both fully qualified.
#define LISTA_STAGE_PLUGIN(info_fn, StageClass)                                               \
  namespace lista_plugin_detail {                                                             \
  static void register_stages(::lista::Registrar& r) { r.add(info_fn(), ::lista::factory_of<StageClass>()); } \
  }                                                                                           \
  LISTA_PLUGIN(lista_plugin_detail::register_stages)
