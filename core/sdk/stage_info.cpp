#include <lista/data.hpp>
#include <lista/stage.hpp>

#include <algorithm>
#include <set>

namespace lista {

const ParamSpec* StageInfo::param(const std::string& n) const {
  for (const auto& p : params)
    if (p.name == n) return &p;
  return nullptr;
}

const ParamRename* StageInfo::renamed_from(const std::string& old_name) const {
  for (const auto& r : renamed)
    if (r.old_name == old_name) return &r;
  return nullptr;
}

const PortSpec* StageInfo::input(const std::string& n) const {
  for (const auto& p : inputs)
    if (p.name == n) return &p;
  return nullptr;
}

const PortSpec* StageInfo::output(const std::string& n) const {
  for (const auto& p : outputs)
    if (p.name == n) return &p;
  return nullptr;
}

std::string StageInfo::declaration_problem() const {
  std::set<std::string> seen;
  for (const auto& p : params) {
    if (!seen.insert(p.name).second) return "declares parameter '" + p.name + "' twice";
    if (p.min && p.max && *p.min > *p.max)
      return "parameter '" + p.name + "': its range " + p.range_text() + " is empty (lower bound above upper)";
    if (std::string why = p.check(p.default_value); !why.empty())
      return "parameter '" + p.name + "': its default " + why;
  }
  std::set<std::string> old;
  for (const auto& r : renamed) {
    if (!old.insert(r.old_name).second) return "renames parameter '" + r.old_name + "' twice";
    if (param(r.old_name)) return "renames '" + r.old_name + "', which is still a parameter";
    if (!param(r.new_name)) return "renames '" + r.old_name + "' to '" + r.new_name + "', which is no parameter";
  }
  const auto& types = port_types();
  for (const auto* ports : {&inputs, &outputs}) {
    const char* side = ports == &inputs ? "input" : "output";
    seen.clear();
    for (const auto& port : *ports) {
      if (!seen.insert(port.name).second) return std::string("declares ") + side + " '" + port.name + "' twice";
      if (std::find(types.begin(), types.end(), port.type) == types.end()) {
        std::string known;
        for (const auto& t : types) known += (known.empty() ? "" : ", ") + t;
        return std::string(side) + " '" + port.name + "' has type '" + port.type + "', which is not a port type (" +
               known + ")";
      }
    }
  }
  return {};
}

}  // namespace lista
