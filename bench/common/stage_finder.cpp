#include <lista_bench/stage_finder.hpp>

#include <lista_core/text.hpp>

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

}  // namespace lista::bench
