// Plugin loading with Boost.DLL: RTLD_NOW, manifest checked (SDK version and
// build fingerprint) before any plugin code runs, libraries never unloaded.
#pragma once

#include <lista_core/registry.hpp>

#include <string>
#include <vector>

namespace lista::core {

// Loads one library and registers its stages. Throws lista::Error naming the
// file and the cause (dlerror text, missing manifest, ABI mismatch, duplicate).
// Loading the same file twice is a no-op.
void load_plugin_library(Registry& registry, const std::string& path);

struct LoadResult {
  std::vector<std::string> loaded;  // libraries loaded
  std::vector<std::string> errors;  // one line per library that failed
};

// The folders searched, in order: LISTA_PLUGIN_PATH (colon-separated), then
// `extra_dirs` (--plugin-dir), then lista-plugins next to liblista_core.so
// (unless include_default is false).
std::vector<std::string> plugin_search_path(const std::vector<std::string>& extra_dirs,
                                            bool include_default = true);

// Loads every lib*.so in `dirs` (missing folders are skipped; files in
// name order). A failing library is reported and the others still load.
LoadResult load_plugins(Registry& registry, const std::vector<std::string>& dirs);

// Folder of liblista_core.so itself.
std::string core_library_dir();

}  // namespace lista::core
