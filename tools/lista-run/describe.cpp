#include "describe.hpp"

#include <nlohmann/json.hpp>

#include <sstream>

namespace lista_run {

using nlohmann::json;

namespace {

json value_json(const lista::ParamValue& v) {
  switch (v.index()) {
    case 0: return std::get<bool>(v);
    case 1: return std::get<int64_t>(v);
    case 2: return std::get<double>(v);
    case 3: return std::get<std::string>(v);
    case 4: return std::get<std::vector<double>>(v);
    default: return std::get<std::vector<std::string>>(v);
  }
}

json ports_json(const std::vector<lista::PortSpec>& ports, bool inputs) {
  json out = json::array();
  for (const auto& p : ports) {
    json j{{"name", p.name}, {"type", p.type}, {"doc", p.doc}};
    if (inputs) j["optional"] = p.optional;
    out.push_back(j);
  }
  return out;
}

json diagnostic_json(const lista::core::Diagnostic& d) {
  return json{{"file", d.where.file}, {"line", d.where.line}, {"column", d.where.column},
              {"stage", d.stage}, {"message", d.message}};
}

}  // namespace

std::string list_plugins(const lista::core::Registry& registry) {
  std::ostringstream os;
  size_t width = 0;
  for (const auto& name : registry.names()) width = std::max(width, name.size());
  std::string kind;
  for (const auto& name : registry.names()) {
    const auto& info = registry.find(name)->info;
    if (info.kind() != kind) {
      kind = info.kind();
      os << (os.tellp() > 0 ? "\n" : "") << kind << ":\n";
    }
    os << "  " << name << std::string(width - name.size() + 2, ' ') << info.version << "  " << info.summary << "\n";
  }
  if (registry.size() == 0)
    os << "no plugins found (searched LISTA_PLUGIN_PATH, --plugin-dir and, unless --no-default-plugins, "
          "lib/lista-plugins)\n";
  return os.str();
}

std::string describe_text(const lista::core::RegisteredStage& stage) {
  const auto& info = stage.info;
  std::ostringstream os;
  os << info.name << " " << info.version << "  (kind: " << info.kind() << ")\n";
  os << "  " << info.summary << "\n";
  if (!info.doc.empty()) os << "\n" << info.doc << "\n";
  os << "\nlibrary: " << (stage.library.empty() ? "(built in)" : stage.library) << "\n";
  os << "\ninputs:\n";
  if (info.inputs.empty()) os << "  (none)\n";
  for (const auto& p : info.inputs)
    os << "  " << p.name << " : " << p.type << (p.optional ? " (optional)" : "") << "  " << p.doc << "\n";
  os << "outputs:\n";
  if (info.outputs.empty()) os << "  (none)\n";
  for (const auto& p : info.outputs) os << "  " << p.name << " : " << p.type << "  " << p.doc << "\n";
  os << "parameters:\n";
  if (info.params.empty()) os << "  (none)\n";
  for (const auto& p : info.params) {
    os << "  " << p.name << " : " << lista::to_string(p.type) << " = " << lista::to_string(p.default_value);
    if (!p.unit_label.empty()) os << " " << p.unit_label;
    if (auto r = p.range_text(); !r.empty()) os << "  range " << r;
    if (!p.choices.empty()) {
      os << "  one of";
      for (const auto& c : p.choices) os << " " << c;
    }
    os << "\n      " << p.doc << "\n";
  }
  if (!info.renamed.empty()) os << "renamed (the old names work until the next release):\n";
  for (const auto& r : info.renamed) os << "  " << r.old_name << " -> " << r.new_name << "\n";
  return os.str();
}

std::string describe_json(const lista::core::RegisteredStage& stage) {
  const auto& info = stage.info;
  json params = json::array();
  for (const auto& p : info.params) {
    json j{{"name", p.name}, {"type", lista::to_string(p.type)}, {"default", value_json(p.default_value)},
           {"doc", p.doc}, {"unit", p.unit_label}};
    j["min"] = p.min ? json(*p.min) : json(nullptr);
    j["max"] = p.max ? json(*p.max) : json(nullptr);
    j["choices"] = p.choices;
    params.push_back(j);
  }
  json j{{"name", info.name},       {"kind", info.kind()},     {"version", info.version},
         {"summary", info.summary}, {"doc", info.doc},         {"library", stage.library},
         {"inputs", ports_json(info.inputs, true)}, {"outputs", ports_json(info.outputs, false)},
         {"params", params}};
  j["renamed"] = json::array();
  for (const auto& r : info.renamed) j["renamed"].push_back({{"old", r.old_name}, {"new", r.new_name}});
  return j.dump(2) + "\n";
}

std::string verdict_json(const lista::core::Diagnostics& d) {
  json errors = json::array(), warnings = json::array();
  for (const auto& e : d.errors) errors.push_back(diagnostic_json(e));
  for (const auto& w : d.warnings) warnings.push_back(diagnostic_json(w));
  return json{{"valid", d.ok()}, {"errors", errors}, {"warnings", warnings}}.dump(2) + "\n";
}

}  // namespace lista_run
