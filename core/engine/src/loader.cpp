// Boost.DLL is used only here.
#include <lista_core/loader.hpp>

#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>

#include <dlfcn.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <set>

namespace lista::core {

namespace fs = std::filesystem;

namespace {

// Libraries stay loaded for the life of the process: stage objects and data
// created by plugin code must never outlive their code.
std::mutex& libraries_mutex() {
  static std::mutex m;
  return m;
}
std::vector<boost::dll::shared_library>& kept_libraries() {
  static auto* libs = new std::vector<boost::dll::shared_library>();  // never destroyed
  return *libs;
}

// Collects a library's stages first, so a library with one bad or duplicate
// stage adds none.
class StagingRegistrar : public Registrar {
 public:
  void add(StageInfo info, StageFactory factory) override {
    staged.push_back({std::move(info), std::move(factory)});
  }
  std::vector<std::pair<StageInfo, StageFactory>> staged;
};

}  // namespace

void load_plugin_library(Registry& registry, const std::string& path) {
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(path, ec);
  const std::string key = ec ? path : canonical.string();
  if (registry.has_library(key)) return;
  if (!fs::exists(path)) throw Error(path + ": plugin library not found");

  boost::dll::shared_library lib;
  try {
    lib.load(boost::dll::fs::path(path), boost::dll::load_mode::rtld_now);
  } catch (const std::exception& e) {
    // Boost wraps dlerror(); ask the loader once more for its own words.
    std::string cause = e.what();
    if (void* h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL); h == nullptr) {
      if (const char* d = dlerror()) cause = d;
    } else {
      dlclose(h);
    }
    // dlerror() starts with the path itself; say it once.
    if (cause.rfind(path + ": ", 0) == 0) cause.erase(0, path.size() + 2);
    // A LiSTA symbol the core lacks: the plugin was built against other SDK
    // headers, or with the old string ABI, before its fingerprint could be read.
    if (cause.find("undefined symbol: _ZN5lista") != std::string::npos ||
        cause.find("undefined symbol: _ZNK5lista") != std::string::npos)
      cause += " (a LiSTA SDK symbol this core does not have: the plugin was built against other SDK headers or "
               "with another C++ string ABI, e.g. -D_GLIBCXX_USE_CXX11_ABI=0; rebuild it against this LiSTA)";
    throw Error(path + ": cannot load plugin library: " + cause);
  }
  if (!lib.has("lista_plugin_manifest"))
    throw Error(path + ": not a LiSTA plugin (no 'lista_plugin_manifest' entry point; use LISTA_PLUGIN(...))");

  const PluginManifest* manifest = nullptr;
  try {
    manifest = lib.get_alias<const PluginManifest*()>("lista_plugin_manifest")();
  } catch (const std::exception& e) {
    throw Error(path + ": cannot read plugin manifest: " + e.what());
  }
  if (manifest == nullptr) throw Error(path + ": plugin manifest is null");
  if (manifest->sdk_version != LISTA_SDK_VERSION)
    throw Error(path + ": built for LiSTA SDK version " + std::to_string(manifest->sdk_version) +
                ", this core has version " + std::to_string(LISTA_SDK_VERSION) + "; rebuild the plugin");
  const std::string fingerprint = manifest->build_fingerprint ? manifest->build_fingerprint : "";
  if (fingerprint != LISTA_BUILD_FINGERPRINT)
    throw Error(path + ": built with '" + fingerprint + "', this core with '" +
                LISTA_BUILD_FINGERPRINT + "' (ABI mismatch); rebuild the plugin with the same toolchain");
  if (manifest->register_stages == nullptr) throw Error(path + ": plugin manifest has no register function");

  StagingRegistrar staging;
  try {
    manifest->register_stages(staging);
  } catch (const std::exception& e) {
    throw Error(path + ": plugin registration failed: " + e.what());
  }
  // Check every name before adding any.
  std::set<std::string> names;
  for (const auto& [info, factory] : staging.staged) {
    if (std::string why = info.declaration_problem(); !why.empty())
      throw Error(path + ": stage '" + info.name + "' " + why);
    if (const auto* existing = registry.find(info.name)) {
      registry.note_refused(info.name, key);
      throw Error("plugin '" + info.name + "' is provided twice: by " +
                  (existing->library.empty() ? std::string("the program itself") : existing->library) +
                  " and by " + path + " (the first one found is used)");
    }
    if (!names.insert(info.name).second)
      throw Error(path + ": registers plugin '" + info.name + "' twice");
  }
  registry.set_current_library(key);
  for (auto& [info, factory] : staging.staged) registry.add(std::move(info), std::move(factory));
  registry.set_current_library("");

  std::lock_guard<std::mutex> lock(libraries_mutex());
  kept_libraries().push_back(std::move(lib));
  registry.mark_library_loaded(key);
}

std::string core_library_dir() {
  boost::dll::fs::error_code ec;
  const auto self = boost::dll::this_line_location(ec);
  return ec ? std::string() : self.parent_path().string();
}

std::vector<std::string> plugin_search_path(const std::vector<std::string>& extra_dirs, bool include_default) {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("LISTA_PLUGIN_PATH")) {
    std::string s = env;
    size_t start = 0;
    while (start <= s.size()) {
      const size_t end = s.find(':', start);
      const std::string part = s.substr(start, end == std::string::npos ? std::string::npos : end - start);
      if (!part.empty()) dirs.push_back(part);
      if (end == std::string::npos) break;
      start = end + 1;
    }
  }
  dirs.insert(dirs.end(), extra_dirs.begin(), extra_dirs.end());
  if (include_default) {
    const std::string core_dir = core_library_dir();
    if (!core_dir.empty()) dirs.push_back((fs::path(core_dir) / "lista-plugins").string());
  }
  return dirs;
}

LoadResult load_plugins(Registry& registry, const std::vector<std::string>& dirs) {
  LoadResult result;
  std::set<std::string> seen;
  for (const auto& dir : dirs) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;  // missing folders are normal (e.g. no install)
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.size() > 6 && name.rfind("lib", 0) == 0 && name.substr(name.size() - 3) == ".so" &&
          entry.is_regular_file(ec))
        files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      const std::string key = fs::weakly_canonical(f, ec).string();
      if (!seen.insert(ec ? f.string() : key).second) continue;
      try {
        load_plugin_library(registry, f.string());
        result.loaded.push_back(f.string());
      } catch (const Error& e) {
        result.errors.push_back(e.what());
      }
    }
  }
  return result;
}

}  // namespace lista::core
