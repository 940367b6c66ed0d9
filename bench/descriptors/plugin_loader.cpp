#include "plugin_loader.hpp"

#include <lista/plugin.hpp>

#include <boost/dll/shared_library.hpp>

#include <cstring>
#include <filesystem>
#include <vector>

namespace lista::bench {
namespace {

struct Collect : Registrar {
  std::vector<LoadedStage> stages;
  void add(StageInfo info, StageFactory factory) override { stages.push_back({std::move(info), std::move(factory)}); }
};

std::vector<boost::dll::shared_library>& kept() {
  static auto* libs = new std::vector<boost::dll::shared_library>();  // plugins are never unloaded
  return *libs;
}

}  // namespace

LoadedStage load_stage(const std::string& plugin_dir, const std::string& name) {
  std::string file = "liblista_" + name + ".so";
  for (char& c : file)
    if (c == '.' && &c != &file[file.size() - 3]) c = '_';
  const std::filesystem::path path = std::filesystem::path(plugin_dir) / file;
  if (!std::filesystem::exists(path)) throw Error("plugin '" + name + "' not found at " + path.string());
  boost::dll::shared_library lib;
  try {
    lib.load(path.string(), boost::dll::load_mode::rtld_now);
  } catch (const std::exception& e) {
    throw Error("cannot load " + path.string() + ": " + e.what());
  }
  const PluginManifest* m = lib.get_alias<const PluginManifest*()>("lista_plugin_manifest")();
  if (m->sdk_version != LISTA_SDK_VERSION || std::strcmp(m->build_fingerprint, LISTA_BUILD_FINGERPRINT) != 0)
    throw Error(path.string() + " was built for another SDK (" + m->build_fingerprint + ")");
  Collect c;
  m->register_stages(c);
  kept().push_back(std::move(lib));
  for (auto& s : c.stages)
    if (s.info.name == name) return s;
  throw Error(path.string() + " does not provide stage '" + name + "'");
}

}  // namespace lista::bench
