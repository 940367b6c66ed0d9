// Checks a parsed pipeline against the registry and orders it. Every problem
// is collected so the user fixes the file in one pass.
#include <lista_core/plan.hpp>
#include <lista_core/text.hpp>

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <sstream>

namespace lista::core {

namespace {

std::vector<std::string> param_names(const StageInfo& info) {
  std::vector<std::string> out;
  for (const auto& p : info.params) out.push_back(p.name);
  return out;
}

// " (did you mean 'x'?)" for an unknown parameter: x a parameter, the new
// name of an old one, or a group's parameter written without its group.
std::string param_suggestion(const std::string& name, const StageInfo& info) {
  std::map<std::string, std::string> means;  // a spelling -> the parameter it suggests
  for (const auto& p : info.params) means.emplace(p.name, p.name);
  for (const auto& r : info.renamed) means.emplace(r.old_name, r.new_name);
  for (const auto& p : info.params) means.emplace(p.name.substr(p.name.rfind('.') + 1), p.name);
  std::vector<std::string> spellings;
  for (const auto& [spelling, param] : means) spellings.push_back(spelling);
  const std::vector<std::string> close = similar_names(name, spellings);
  return close.empty() ? std::string() : " (did you mean '" + means.at(close.front()) + "'?)";
}

std::vector<std::string> port_names(const std::vector<PortSpec>& ports) {
  std::vector<std::string> out;
  for (const auto& p : ports) out.push_back(p.name);
  return out;
}

std::string list_or_none(const std::vector<std::string>& names) {
  if (names.empty()) return "none";
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// Resolves parameters: defaults, then the file, then --set overrides.
Params resolve_params(const StageSpec& s, const StageInfo& info, const std::vector<const Override*>& overrides,
                      Diagnostics& d) {
  Params params = Params::defaults(info.params);
  auto apply = [&](const std::string& name, const std::optional<ParamValue>& value, const std::string& problem,
                   const SourceLocation& at, const SourceLocation& key_at, const std::string& origin) {
    const ParamSpec* spec = info.param(name);
    if (!spec) {
      d.error(key_at, s.id, origin + "unknown parameter '" + name + "' for " + info.name +
                            param_suggestion(name, info) + "; known: " + list_or_none(param_names(info)));
      return;
    }
    std::optional<ParamValue> typed = value;
    // An empty array takes its element type from the declaration.
    if (!typed && problem == kEmptyArrayProblem) {
      if (spec->type == ParamType::real_list) typed = ParamValue(std::vector<double>{});
      if (spec->type == ParamType::text_list) typed = ParamValue(std::vector<std::string>{});
    }
    if (!typed) {
      d.error(at, s.id, origin + "parameter '" + name + "': " + problem);
      return;
    }
    const std::optional<ParamValue>& value_ = typed;
    if (std::string why = spec->check(*value_); !why.empty()) {
      d.error(at, s.id, origin + "parameter '" + name + "' " + why);
      return;
    }
    ParamValue v = *value_;
    // An integer written for a real parameter is stored as a real.
    if (spec->type == ParamType::real && v.index() == 1) v = double(std::get<int64_t>(v));
    params.set(name, std::move(v), true, at);
  };
  // An old name fills the new parameters and says how they are spelled now;
  // in the file, a parameter written under both names is an error.
  std::map<std::string, std::string> spelled;  // parameter -> the name the file wrote it under
  auto put = [&](const std::string& name, const std::optional<ParamValue>& value, const std::string& problem,
                 const SourceLocation& at, const SourceLocation& key_at, const std::string& origin) {
    std::vector<std::pair<std::string, std::optional<ParamValue>>> targets{{name, value}};
    if (const ParamRename* r = info.param(name) ? nullptr : info.renamed_from(name)) {
      ParamAssignments as;
      try {
        if (value) as = r->assignments(*value);
      } catch (const Error& e) {
        d.error(at, s.id, origin + e.message());
        return;
      }
      d.warning(key_at, s.id, origin + r->warning(value.value_or(ParamValue()), as));
      targets = {{r->new_name, value}};
      if (value) targets.assign(as.begin(), as.end());
    }
    for (const auto& [target, v] : targets) {
      if (origin.empty() && !spelled.emplace(target, name).second) {
        d.error(key_at, s.id, "parameter '" + target + "' is written twice, as '" + spelled[target] + "' and as '" +
                                  name + "'; keep '" + target + "'");
        return;
      }
      apply(target, v, problem, at, key_at, origin);
    }
  };
  for (const auto& p : s.params) put(p.name, p.value, p.problem, p.where, p.key_where, "");
  for (const Override* o : overrides) {
    const std::string origin = "--set " + o->text + ": ";
    // Not parameters but the pipeline's structure: say so instead of "unknown parameter".
    if (!info.param(o->param) && o->param == "plugin") {
      d.error(s.where, s.id, origin + "a stage's plugin cannot be changed with --set; run a pipeline file that "
                                      "names the other plugin (one-swap ablations are in pipelines/ablations/)");
      continue;
    }
    if (!info.param(o->param) && o->param == "inputs") {
      d.error(s.where, s.id, origin + "a stage's inputs cannot be changed with --set; edit a copy of the pipeline file");
      continue;
    }
    put(o->param, o->value, o->problem, s.where, s.where, origin);
  }
  return params;
}

// Creates the stage once and drops it, so a constructor that refuses its
// parameters together (clamping_min >= clamping_max) fails --validate and
// the plan, not the run after earlier stages spent their time. Empty if fine.
std::string construction_problem(const RegisteredStage& stage, const Params& params) {
  try {
    if (!stage.factory(params)) return "the plugin's factory returned no stage";
    return {};
  } catch (const Error& e) {
    return e.message();
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown exception";
  }
}

void check_construction(const StageSpec& s, const RegisteredStage& stage, const Params& params,
                        const std::vector<const Override*>& overrides, Diagnostics& d) {
  std::string why = construction_problem(stage, params);
  if (why.empty()) return;
  // The stage's table is the location; the --set arguments are not in it, so name them.
  std::string sets;
  for (const Override* o : overrides) sets += (sets.empty() ? "" : " ") + ("--set " + o->text);
  if (!sets.empty()) why += " (with " + sets + ")";
  d.error(s.where, s.id, "parameters refused by " + stage.info.name + ": " + why);
}

void check_inputs(const StageSpec& s, const StageInfo& info, const PipelineSpec& spec, const Registry& registry,
                  Diagnostics& d) {
  // A port whose reference was already reported is not "missing" as well.
  std::set<std::string> connected(s.unusable_inputs.begin(), s.unusable_inputs.end());
  for (const auto& in : s.inputs) {
    const PortSpec* port = info.input(in.port);
    if (!port) {
      d.error(in.where, s.id, "unknown input port '" + in.port + "' for " + info.name +
                                  did_you_mean(in.port, port_names(info.inputs)) +
                                  "; inputs: " + list_or_none(port_names(info.inputs)));
      continue;
    }
    connected.insert(in.port);
    const StageSpec* from = spec.find(in.from_stage);
    if (!from) {
      std::vector<std::string> ids;
      for (const auto& o : spec.stages) ids.push_back(o.id);
      d.error(in.where, s.id, "input '" + in.port + "' refers to unknown stage '" + in.from_stage + "'" +
                                  did_you_mean(in.from_stage, ids));
      continue;
    }
    if (from->id == s.id) {
      d.error(in.where, s.id, "input '" + in.port + "' refers to the stage itself (cycle: " + s.id + " -> " + s.id + ")");
      continue;
    }
    const RegisteredStage* from_stage = registry.find(from->plugin);
    if (!from_stage) continue;  // reported at that stage
    const PortSpec* out = from_stage->info.output(in.from_port);
    if (!out) {
      d.error(in.where, s.id, "input '" + in.port + "': stage '" + from->id + "' (" + from->plugin +
                                  ") has no output '" + in.from_port + "'" +
                                  did_you_mean(in.from_port, port_names(from_stage->info.outputs)) +
                                  "; outputs: " + list_or_none(port_names(from_stage->info.outputs)));
      continue;
    }
    if (out->type != port->type)
      d.error(in.where, s.id, "input '" + in.port + "' expects '" + port->type + "' but " + from->id + "." +
                                  in.from_port + " is '" + out->type + "'");
  }
  for (const auto& port : info.inputs)
    if (!port.optional && !connected.count(port.name))
      d.error(s.where, s.id, "required input '" + port.name + "' (" + port.type +
                                 ") is not connected; add inputs = { " + port.name + " = \"<stage>." +
                                 "<port>\" }");
}

// Kahn's algorithm, taking the earliest stage in file order among the ready
// ones so the plan is stable. Returns the order, or empty with `cycle` filled.
std::vector<size_t> topological_order(const std::vector<std::vector<size_t>>& deps, std::vector<size_t>& cycle) {
  const size_t n = deps.size();
  std::vector<size_t> missing(n);
  std::vector<std::vector<size_t>> users(n);
  for (size_t i = 0; i < n; ++i) {
    missing[i] = deps[i].size();
    for (size_t d : deps[i]) users[d].push_back(i);
  }
  std::set<size_t> ready;
  for (size_t i = 0; i < n; ++i)
    if (missing[i] == 0) ready.insert(i);
  std::vector<size_t> order;
  while (!ready.empty()) {
    const size_t i = *ready.begin();
    ready.erase(ready.begin());
    order.push_back(i);
    for (size_t u : users[i])
      if (--missing[u] == 0) ready.insert(u);
  }
  if (order.size() == n) return order;
  // Walk dependencies among the unordered stages until one repeats: that is a cycle.
  std::vector<int> visited(n, -1);
  size_t at = 0;
  while (missing[at] == 0) ++at;
  std::vector<size_t> path;
  while (visited[at] < 0) {
    visited[at] = static_cast<int>(path.size());
    path.push_back(at);
    for (size_t d : deps[at])
      if (missing[d] != 0) {
        at = d;
        break;
      }
  }
  cycle.assign(path.begin() + visited[at], path.end());
  std::reverse(cycle.begin(), cycle.end());  // producer -> consumer
  return {};
}

}  // namespace

Plan build_plan(const PipelineSpec& spec, const std::vector<Override>& overrides, const Registry& registry,
                Diagnostics& d, const std::vector<std::string>& load_errors) {
  Plan plan;
  plan.spec = spec;

  for (const auto& o : overrides) {
    const StageSpec* s = spec.find(o.stage);
    if (!s) {
      std::vector<std::string> ids;
      for (const auto& st : spec.stages) ids.push_back(st.id);
      if (o.stage == "pipeline") {
        d.error({spec.file, 0, 0}, "", "--set " + o.text + ": [pipeline] settings have their own options: --seed, "
                                           "--threads, --dataset, --out");
        continue;
      }
      d.error({spec.file, 0, 0}, "", "--set " + o.text + ": no stage '" + o.stage + "' in the pipeline" +
                                         did_you_mean(o.stage, ids));
    }
  }

  std::map<std::string, size_t> index_of;
  for (const auto& s : spec.stages) {
    if (index_of.count(s.id)) continue;  // TOML forbids it; defensive
    const RegisteredStage* reg = s.plugin.empty() ? nullptr : registry.find(s.plugin);
    if (!s.plugin.empty() && !reg) {
      std::string msg = "unknown plugin '" + s.plugin + "'" + did_you_mean(s.plugin, registry.names());
      if (!load_errors.empty()) {
        // Quote the library the plugin would live in (liblista_<kind>_<name>.so)
        // if it is among those that failed, else the first.
        std::string stem = s.plugin;
        std::replace_if(stem.begin(), stem.end(), [](char c) { return c == '.' || c == '-'; }, '_');
        const std::string file = "liblista_" + stem + ".so";
        const auto named = std::find_if(load_errors.begin(), load_errors.end(),
                                        [&](const std::string& e) { return e.find("/" + file + ":") != std::string::npos; });
        msg += "; " + std::to_string(load_errors.size()) + " plugin librar" + (load_errors.size() == 1 ? "y" : "ies") +
               " failed to load: " + (named != load_errors.end() ? *named : load_errors.front());
      }
      else
        msg += "; see lista-run --list-plugins";
      d.error(s.plugin_where.known() ? s.plugin_where : s.where, s.id, msg);
    }
    PlannedStage p;
    p.id = s.id;
    p.stage = reg;
    p.where = s.where;
    p.inputs = s.inputs;
    if (reg) {
      std::vector<const Override*> mine;
      for (const auto& o : overrides)
        if (o.stage == s.id) mine.push_back(&o);
      const size_t errors_before = d.errors.size();
      p.params = resolve_params(s, reg->info, mine, d);
      if (d.errors.size() == errors_before) check_construction(s, *reg, p.params, mine, d);
      check_inputs(s, reg->info, spec, registry, d);
      for (const auto& other : registry.refused(s.plugin))
        d.warning(s.plugin_where.known() ? s.plugin_where : s.where, s.id,
                  "plugin '" + s.plugin + "' is provided twice: using " +
                      (reg->library.empty() ? std::string("the program's own") : reg->library) +
                      " (found first on the plugin search path), not " + other);
    }
    index_of[s.id] = plan.stages.size();
    plan.stages.push_back(std::move(p));
  }

  // Graph edges from every reference to an existing stage (even when the port is wrong) so cycles are found too.
  std::vector<std::vector<size_t>> deps(plan.stages.size());
  for (size_t i = 0; i < plan.stages.size(); ++i)
    for (const auto& in : plan.stages[i].inputs)
      if (auto it = index_of.find(in.from_stage); it != index_of.end() && it->second != i &&
                                                  std::find(deps[i].begin(), deps[i].end(), it->second) == deps[i].end())
        deps[i].push_back(it->second);
  std::vector<size_t> cycle;
  const std::vector<size_t> order = topological_order(deps, cycle);
  if (!cycle.empty()) {
    std::string names;
    for (size_t c : cycle) names += plan.stages[c].id + " -> ";
    names += plan.stages[cycle.front()].id;
    d.error(plan.stages[cycle.front()].where, plan.stages[cycle.front()].id, "cycle in the pipeline: " + names);
  }

  // Unused outputs are worth a warning: work done for nothing.
  std::set<std::pair<std::string, std::string>> used;  // (stage, port) some input reads
  for (const auto& s : plan.stages)
    for (const auto& in : s.inputs) used.emplace(in.from_stage, in.from_port);
  for (const auto& s : plan.stages) {
    if (!s.stage) continue;
    for (const auto& out : s.stage->info.outputs)
      if (!used.count({s.id, out.name}))
        d.warning(s.where, s.id, "output '" + out.name + "' (" + out.type + ") is not used by any stage");
  }

  if (!d.ok()) return plan;

  // Reorder topologically and remap dependency indices.
  std::vector<size_t> new_index(plan.stages.size());
  for (size_t k = 0; k < order.size(); ++k) new_index[order[k]] = k;
  std::vector<PlannedStage> sorted;
  for (size_t k = 0; k < order.size(); ++k) {
    PlannedStage s = std::move(plan.stages[order[k]]);
    for (size_t dep : deps[order[k]]) s.depends_on.push_back(new_index[dep]);
    std::sort(s.depends_on.begin(), s.depends_on.end());
    s.level = 0;
    for (size_t dep : s.depends_on) s.level = std::max(s.level, sorted[dep].level + 1);
    plan.levels = std::max(plan.levels, s.level + 1);
    sorted.push_back(std::move(s));
  }
  plan.stages = std::move(sorted);
  return plan;
}

namespace {
std::string quoted(const std::string& s) { return to_string(ParamValue(s)); }
}  // namespace

std::string Plan::resolved_toml() const {
  std::ostringstream os;
  os << "[pipeline]\n";
  if (!spec.name.empty()) os << "name = " << quoted(spec.name) << "\n";
  os << "seed = " << spec.seed.value_or(0) << "\n";
  if (spec.threads) os << "threads = " << *spec.threads << "\n";
  if (!spec.dataset.empty()) os << "dataset = " << quoted(spec.dataset) << "\n";
  if (!spec.output.empty()) os << "output = " << quoted(spec.output) << "\n";
  for (const auto& s : stages) {
    os << "\n[stages." << s.id << "]\n";
    os << "plugin = " << quoted(s.stage ? s.stage->info.name : std::string()) << "\n";
    if (!s.inputs.empty()) {
      os << "inputs = { ";
      for (size_t i = 0; i < s.inputs.size(); ++i)
        os << (i ? ", " : "") << s.inputs[i].port << " = " << quoted(s.inputs[i].from_stage + "." + s.inputs[i].from_port);
      os << " }\n";
    }
    if (s.stage)
      for (const auto& p : s.stage->info.params) os << p.name << " = " << to_string(s.params.value(p.name)) << "\n";
  }
  return os.str();
}

std::string Plan::describe() const {
  std::ostringstream os;
  os << "pipeline " << (spec.name.empty() ? spec.file : spec.name) << ": " << stages.size() << " stages in "
     << levels << " level" << (levels == 1 ? "" : "s") << " (stages of one level may run in parallel)\n";
  for (int level = 0; level < levels; ++level) {
    os << "level " << level << ":\n";
    for (size_t i = 0; i < stages.size(); ++i) {
      const auto& s = stages[i];
      if (s.level != level) continue;
      os << "  " << (i + 1) << ". " << s.id << " (" << s.stage->info.name << " " << s.stage->info.version << ")\n";
      for (const auto& in : s.inputs) os << "       input  " << in.port << " <- " << in.from_stage << "." << in.from_port << "\n";
      for (const auto& p : s.stage->info.params)
        os << "       param  " << p.name << " = " << to_string(s.params.value(p.name))
           << (s.params.is_set(p.name) ? "" : "  (default)") << "\n";
    }
  }
  return os.str();
}

}  // namespace lista::core
