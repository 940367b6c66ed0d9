#include <lista_bench/plugin_settings.hpp>

#include <algorithm>
#include <iostream>

namespace lista::bench {

namespace {

// The parameter `s` sets on plugin (or entry) `name`, empty if it names
// another: "align.posegraph.scans.points" is scans.points of align.posegraph.
std::string param_on(const Setting& s, const std::string& name) {
  const std::string key = s.text.substr(0, s.text.find('='));
  return key.size() > name.size() + 1 && key.compare(0, name.size() + 1, name + ".") == 0 ? key.substr(name.size() + 1)
                                                                                        : std::string();
}

}  // namespace

Setting parse_setting(const std::string& text, const std::string& example) {
  const size_t eq = text.find('='), dot = text.substr(0, eq).rfind('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == eq)
    throw Error("--set '" + text + "' is not of the form <plugin>.<param>=<value> (e.g. " + example + ")");
  return {text, text.substr(0, dot), text.substr(dot + 1, eq - dot - 1),
          core::parse_override("x.y=" + text.substr(eq + 1))};
}

void check_compared(const std::vector<Setting>& settings, const std::vector<std::string>& compared) {
  for (const Setting& s : settings) {
    if (std::any_of(compared.begin(), compared.end(), [&](const std::string& c) { return !param_on(s, c).empty(); }))
      continue;
    std::string list;
    for (const auto& c : compared) list += (list.empty() ? "" : ", ") + c;
    throw Error("--set " + s.text + ": '" + s.plugin + "' is not among the plugins compared (" + list + ")");
  }
}

Params params_of(const std::string& name, const StageInfo& info, const std::vector<Setting>& settings) {
  Params params = Params::defaults(info.params);
  for (const Setting& s : settings) {
    const std::string param = param_on(s, name);
    if (param.empty()) continue;
    const ParamRename* renamed = info.param(param) ? nullptr : info.renamed_from(param);
    if (!info.param(param) && !renamed)
      throw Error("--set " + s.text + ": " + info.name + " has no parameter '" + param + "'");
    if (!s.parsed.value) throw Error("--set " + s.text + ": " + s.parsed.problem);
    ParamAssignments values = {{param, *s.parsed.value}};
    if (renamed) {
      try {
        values = renamed->assignments(*s.parsed.value);
      } catch (const Error& e) {
        throw Error("--set " + s.text + ": " + e.message());
      }
      std::cerr << "warning: --set " << s.text << ": " << renamed->warning(*s.parsed.value, values) << "\n";
    }
    for (auto& [n, v] : values) {
      const ParamSpec* spec = info.param(n);
      if (!spec) throw Error("--set " + s.text + ": " + info.name + " has no parameter '" + n + "'");
      if (std::string why = spec->check(v); !why.empty()) throw Error("--set " + s.text + ": '" + n + "' " + why);
      // 2 for a real parameter is 2.0, as in a pipeline file.
      if (spec->type == ParamType::real && std::holds_alternative<int64_t>(v)) v = double(std::get<int64_t>(v));
      params.set(n, std::move(v));
    }
  }
  return params;
}

}  // namespace lista::bench
