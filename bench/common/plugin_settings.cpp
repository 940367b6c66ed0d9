#include <lista_bench/plugin_settings.hpp>

#include <algorithm>

namespace lista::bench {

Setting parse_setting(const std::string& text, const std::string& example) {
  const size_t eq = text.find('='), dot = text.substr(0, eq).rfind('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == eq)
    throw Error("--set '" + text + "' is not of the form <plugin>.<param>=<value> (e.g. " + example + ")");
  return {text, text.substr(0, dot), text.substr(dot + 1, eq - dot - 1),
          core::parse_override("x.y=" + text.substr(eq + 1))};
}

void check_compared(const std::vector<Setting>& settings, const std::vector<std::string>& compared) {
  for (const Setting& s : settings) {
    if (std::find(compared.begin(), compared.end(), s.plugin) != compared.end()) continue;
    std::string list;
    for (const auto& c : compared) list += (list.empty() ? "" : ", ") + c;
    throw Error("--set " + s.text + ": '" + s.plugin + "' is not among the plugins compared (" + list + ")");
  }
}

Params params_of(const std::string& name, const StageInfo& info, const std::vector<Setting>& settings) {
  Params params = Params::defaults(info.params);
  for (const Setting& s : settings) {
    if (s.plugin != name) continue;
    const ParamSpec* spec = info.param(s.param);
    if (!spec) throw Error("--set " + s.text + ": " + info.name + " has no parameter '" + s.param + "'");
    if (!s.parsed.value) throw Error("--set " + s.text + ": " + s.parsed.problem);
    ParamValue v = *s.parsed.value;
    if (std::string why = spec->check(v); !why.empty()) throw Error("--set " + s.text + ": '" + s.param + "' " + why);
    // 2 for a real parameter is 2.0, as in a pipeline file.
    if (spec->type == ParamType::real && std::holds_alternative<int64_t>(v)) v = double(std::get<int64_t>(v));
    params.set(s.param, std::move(v));
  }
  return params;
}

}  // namespace lista::bench
