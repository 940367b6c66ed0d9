// Finds the stages a benchmark compares the way lista-run does: every plugin
// library on the search path (LISTA_PLUGIN_PATH, then the given folders, then
// the lista-plugins folder next to liblista_core) loaded by the core's loader
// into its registry, so the benchmark measures the very libraries a pipeline
// runs and a third-party plugin is compared beside the shipped ones.
#pragma once

#include <lista_core/loader.hpp>
#include <lista_core/registry.hpp>

#include <string>
#include <vector>

namespace lista::bench {

class StageFinder {
 public:
  explicit StageFinder(const std::vector<std::string>& plugin_dirs, bool include_default = true);
  // The stage called `name`; throws lista::Error naming similar stages and
  // the libraries that failed to load when there is none.
  const core::RegisteredStage& find(const std::string& name) const;
  // The same, for a stage that must take one `input` port and give one
  // `output` port (port types, e.g. "objects" and "descriptors"); throws
  // naming `kind` ("a descriptor stage") otherwise. Warns on stderr, as
  // `program`, when another library offered the same name (lista-run does too).
  const core::RegisteredStage& find(const std::string& name, const std::string& input, const std::string& output,
                                    const std::string& kind, const std::string& program) const;
  // Libraries that offered a stage name already taken (lista-run warns too).
  const std::vector<std::string>& refused(const std::string& name) const { return registry_.refused(name); }

 private:
  core::Registry registry_;
  core::LoadResult loaded_;
};

}  // namespace lista::bench
