// `--set <plugin>.<param>=<value>` as the benchmarks take it. A benchmark runs
// plugins outside a pipeline, so a setting names the plugin (or a compared
// entry's own name, as lista-bench descriptors --plugins mine=...) where
// lista-run's --set names a stage id. The value is parsed as lista-run parses
// it (a TOML value; a bare word is a string) and checked against the plugin's
// declaration: a typo, a wrong type or a value out of range is a one-line
// error before anything runs, never a silently kept default.
#pragma once

#include <lista/lista.hpp>
#include <lista_core/pipeline.hpp>

#include <string>
#include <vector>

namespace lista::bench {

struct Setting {
  std::string text;    // as given
  std::string plugin;  // before the last '.' of the part ahead of '=' (a group's
  std::string param;   // parameter, plugin.group.key, is matched by the plugin's name)
  core::Override parsed;  // its value, or why there is none
};

// Throws lista::Error when `text` is not <plugin>.<param>=<value>; the
// message shows `example` (e.g. "align.posegraph.scan_edges=0").
Setting parse_setting(const std::string& text, const std::string& example);

// Throws lista::Error for the first setting whose plugin is not one of
// `compared`: a setting for a plugin the run leaves out would do nothing.
void check_compared(const std::vector<Setting>& settings, const std::vector<std::string>& compared);

// `info`'s defaults with every setting naming `name` applied (an old name of
// a renamed parameter with a warning on stderr, as lista-run). Throws
// lista::Error naming the setting for a parameter `info` does not declare or
// a value its declaration refuses (type, range, choices).
Params params_of(const std::string& name, const StageInfo& info, const std::vector<Setting>& settings);

}  // namespace lista::bench
