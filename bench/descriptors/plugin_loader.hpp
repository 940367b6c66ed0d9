// Loads describe.* plugins by file, the way the core does (Boost.DLL alias
// `lista_plugin_manifest`, SDK version and fingerprint checked), so the
// benchmark measures the very libraries a pipeline would run.
#pragma once

#include <lista/stage.hpp>

#include <string>

namespace lista::bench {

struct LoadedStage {
  StageInfo info;
  StageFactory factory;
};

// Finds stage `name` (e.g. "describe.esf") in <plugin_dir>/liblista_<kind>_<name>.so.
// Throws lista::Error if the file is missing, refused or lacks the stage.
LoadedStage load_stage(const std::string& plugin_dir, const std::string& name);

}  // namespace lista::bench
