#include <lista_core/registry.hpp>
#include <lista_core/text.hpp>

#include <algorithm>
#include <cctype>

namespace lista::core {

void Registry::add(StageInfo info, StageFactory factory) {
  const std::string where = current_library_.empty() ? "the program itself" : current_library_;
  // A name is written in TOML (plugin = "kind.name") and on command lines
  // (--set, --plugins, --describe): letters, digits, '_', '-' and dots.
  const bool plain = std::all_of(info.name.begin(), info.name.end(), [](unsigned char c) {
    return std::isalnum(c) || c == '_' || c == '-' || c == '.';
  });
  if (info.name.empty() || !plain || info.name.find('.') == std::string::npos || info.name.front() == '.' ||
      info.name.back() == '.')
    throw Error("stage name '" + info.name + "' from " + where +
                " is not of the form <kind>.<name> (letters, digits, '_', '-' and dots)");
  if (!factory) throw Error("stage '" + info.name + "' from " + where + " has no factory");
  if (std::string why = info.declaration_problem(); !why.empty())
    throw Error(where + ": stage '" + info.name + "' " + why);
  if (auto it = stages_.find(info.name); it != stages_.end()) {
    const std::string first = it->second.library.empty() ? "the program itself" : it->second.library;
    throw Error("plugin '" + info.name + "' is provided twice: by " + first + " and by " + where);
  }
  std::string name = info.name;
  stages_.emplace(std::move(name), RegisteredStage{std::move(info), std::move(factory), current_library_});
}

const RegisteredStage* Registry::find(const std::string& name) const {
  auto it = stages_.find(name);
  return it == stages_.end() ? nullptr : &it->second;
}

const std::vector<std::string>& Registry::refused(const std::string& name) const {
  static const std::vector<std::string> none;
  auto it = refused_.find(name);
  return it == refused_.end() ? none : it->second;
}

std::vector<std::string> Registry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, stage] : stages_) out.push_back(name);
  return out;
}

std::vector<std::string> Registry::similar(const std::string& name) const {
  return similar_names(name, names());
}

}  // namespace lista::core
