#include <lista_bench/stage_finder.hpp>

#include <lista_core/text.hpp>

#include <cstdio>

namespace lista::bench {

StageFinder::StageFinder(const std::vector<std::string>& plugin_dirs, bool include_default) {
  loaded_ = core::load_plugins(registry_, core::plugin_search_path(plugin_dirs, include_default));
}

const core::RegisteredStage& StageFinder::find(const std::string& name) const {
  if (const core::RegisteredStage* s = registry_.find(name)) return *s;
  std::string msg = "unknown plugin '" + name + "'" + core::did_you_mean(name, registry_.names());
  if (!loaded_.errors.empty())
    msg += "; " + std::to_string(loaded_.errors.size()) + " plugin librar" +
           (loaded_.errors.size() == 1 ? "y" : "ies") + " failed to load: " + loaded_.errors.front();
  else
    msg += "; see lista-run --list-plugins (a plugin of your own: --plugin-dir FOLDER)";
  throw Error(msg);
}

const core::RegisteredStage& StageFinder::find(const std::string& name, const std::string& input,
                                              const std::string& output, const std::string& kind,
                                              const std::string& program) const {
  const core::RegisteredStage& stage = find(name);
  if (stage.info.inputs.size() != 1 || stage.info.inputs[0].type != input || stage.info.outputs.size() != 1 ||
      stage.info.outputs[0].type != output)
    throw Error(name + " is not " + kind + " (one '" + input + "' input, one '" + output + "' output)");
  for (const auto& other : registry_.refused(name))
    std::fprintf(stderr, "%s: warning: plugin '%s' is provided twice: using %s, not %s\n", program.c_str(),
                 name.c_str(), stage.library.c_str(), other.c_str());
  return stage;
}

}  // namespace lista::bench
