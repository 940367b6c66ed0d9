// toml11 is used only here: the TOML file becomes a PipelineSpec with a
// source location on everything a later message may point at.
#include <lista_core/pipeline.hpp>
#include <lista_core/text.hpp>

#include <lista/toml_prechecks.hpp>

#include <toml.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <filesystem>
#include <fstream>
#include <regex>
#include <cctype>
#include <sstream>
#include <tuple>

namespace lista::core {

namespace {

// Line, column and text of the line where `v` starts. toml11's own
// location() counts the newlines from the file's start on every call, which
// made checking a pipeline of n stages take O(n^2) (10 000 stages: minutes);
// here each source is indexed once.
struct Located {
  int line = 0, column = 0;
  std::string line_text;
};

Located locate(const toml::value& v) {
  const auto* reg = dynamic_cast<const toml::detail::region*>(toml::detail::get_region(v));
  if (!reg || !reg->source()) {
    const auto loc = v.location();
    return {static_cast<int>(loc.line()), static_cast<int>(loc.column()), loc.line_str()};
  }
  thread_local std::shared_ptr<const std::vector<char>> indexed;
  thread_local std::vector<size_t> newlines;
  const std::vector<char>& text = *reg->source();
  if (indexed != reg->source()) {
    indexed = reg->source();
    newlines.clear();
    for (size_t i = 0; i < text.size(); ++i)
      if (text[i] == '\n') newlines.push_back(i);
  }
  const size_t offset = static_cast<size_t>(reg->first() - reg->begin());
  const auto next = std::lower_bound(newlines.begin(), newlines.end(), offset);
  const size_t line = static_cast<size_t>(next - newlines.begin()) + 1;
  const size_t start = line == 1 ? 0 : newlines[line - 2] + 1;
  const size_t end = next == newlines.end() ? text.size() : *next;
  return {static_cast<int>(line), static_cast<int>(offset - start + 1),
          std::string(text.begin() + static_cast<std::ptrdiff_t>(start), text.begin() + static_cast<std::ptrdiff_t>(end))};
}

SourceLocation where(const toml::value& v, const std::string& file) {
  const Located at = locate(v);
  SourceLocation s;
  s.file = file;
  s.line = at.line;
  s.column = at.column;
  return s;
}

// The key of a `key = value` line: toml11 3.7 keeps no location for keys,
// so search the value's line for the key before the value. Falls back to
// the value's column (dotted or unusual keys).
SourceLocation key_where(const toml::value& v, const std::string& key, const std::string& file) {
  SourceLocation s = where(v, file);
  const std::string line = locate(v).line_text;
  const size_t limit = std::min(line.size(), static_cast<size_t>(std::max(0, s.column - 1)));
  auto is_key_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-'; };
  for (size_t pos = line.rfind(key, limit); pos != std::string::npos && !key.empty();
       pos = pos == 0 ? std::string::npos : line.rfind(key, pos - 1)) {
    const size_t end = pos + key.size();
    if (end > limit || (pos > 0 && is_key_char(line[pos - 1])) || (end < line.size() && is_key_char(line[end])))
      continue;
    const bool quoted = pos > 0 && (line[pos - 1] == '"' || line[pos - 1] == '\'');
    s.column = static_cast<int>(pos) + (quoted ? 0 : 1);
    return s;
  }
  return s;
}

bool valid_id(const std::string& id) {
  static const std::regex re("[A-Za-z_][A-Za-z0-9_-]*");
  return std::regex_match(id, re);
}

const char* toml_type_name(const toml::value& v) {
  switch (v.type()) {
    case toml::value_t::boolean: return "bool";
    case toml::value_t::integer: return "int";
    case toml::value_t::floating: return "float";
    case toml::value_t::string: return "string";
    case toml::value_t::array: return "array";
    case toml::value_t::table: return "table";
    default: return "date/time";
  }
}

// A TOML value as a parameter value, or the reason it cannot be one.
std::optional<ParamValue> to_param(const toml::value& v, std::string& problem) {
  // toml11 clamps a number it cannot hold (1e400, a 20-digit integer) to the
  // type's limit instead of failing: such a value is not what was written.
  const char* too_big = "the number is too large for a 64-bit value";
  switch (v.type()) {
    case toml::value_t::boolean: return ParamValue(v.as_boolean());
    case toml::value_t::integer: {
      const int64_t i = v.as_integer();
      if (i == std::numeric_limits<int64_t>::max() || i == std::numeric_limits<int64_t>::min()) {
        problem = too_big;
        return std::nullopt;
      }
      return ParamValue(i);
    }
    case toml::value_t::floating: {
      const double d = v.as_floating();
      if (std::abs(d) == std::numeric_limits<double>::max()) {
        problem = too_big;
        return std::nullopt;
      }
      return ParamValue(d);
    }
    case toml::value_t::string: return ParamValue(static_cast<std::string>(v.as_string()));
    case toml::value_t::array: {
      const auto& a = v.as_array();
      if (a.empty()) {
        problem = kEmptyArrayProblem;
        return std::nullopt;
      }
      bool all_numbers = true, all_strings = true;
      for (const auto& e : a) {
        all_numbers &= e.is_integer() || e.is_floating();
        all_strings &= e.is_string();
      }
      if (all_numbers) {
        std::vector<double> out;
        for (const auto& e : a) out.push_back(e.is_integer() ? double(e.as_integer()) : double(e.as_floating()));
        return ParamValue(std::move(out));
      }
      if (all_strings) {
        std::vector<std::string> out;
        for (const auto& e : a) out.push_back(e.as_string());
        return ParamValue(std::move(out));
      }
      problem = "arrays must hold only numbers or only strings";
      return std::nullopt;
    }
    default:
      problem = std::string("a ") + toml_type_name(v) + " is not a parameter value";
      return std::nullopt;
  }
}

// The first line of a toml11 error message, without its "[error] " prefix.
std::string first_line(const std::string& what) {
  std::string s = what.substr(0, what.find('\n'));
  if (s.rfind("[error] ", 0) == 0) s = s.substr(8);
  return s;
}

// The mistakes people make most, said plainly instead of in toml11's words (the parser's
// own text is kept for everything else).
std::string plain_syntax_message(const std::string& toml_text) {
  static const std::vector<std::pair<std::regex, std::string>> known = {
      {std::regex(R"re(toml::insert_value: table \("stages\.([^"]+)"\) already exists.*)re"),
       "stage '$1' is defined twice; stage ids are unique, rename one"},
      {std::regex(R"re(toml::insert_value: table \("([^"]+)"\) already exists.*)re"), "table [$1] is defined twice"},
      {std::regex(R"re(toml::insert_value: value \("([^"]+)"\) already exists.*)re"),
       "key '$1' is given twice in its table"},
      {std::regex(R"re(toml::parse_basic_string: the next token is not a valid string.*)re"),
       "a string is not closed (a missing \" before the end of the line?)"},
      {std::regex(R"re((bad format: unknown value appeared|toml::parse_boolean:).*)re"),
       "not a TOML value (text needs quotes: key = \"text\"; lists need brackets: [1.0, 2.0])"},
  };
  for (const auto& [pattern, plain] : known)
    if (std::regex_match(toml_text, pattern)) return std::regex_replace(toml_text, pattern, plain);
  return toml_text;
}

// A table's entries in the order the file has them (toml11 keeps a hash
// map), so diagnostics come out line by line.
std::vector<std::pair<const std::string*, const toml::value*>> in_file_order(const toml::value& table) {
  std::vector<std::tuple<int, int, const std::string*, const toml::value*>> keyed;
  for (const auto& [key, v] : table.as_table()) {
    const Located at = locate(v);
    keyed.emplace_back(at.line, at.column, &key, &v);
  }
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
    return std::make_tuple(std::get<0>(a), std::get<1>(a), *std::get<2>(a)) <
           std::make_tuple(std::get<0>(b), std::get<1>(b), *std::get<2>(b));
  });
  std::vector<std::pair<const std::string*, const toml::value*>> out;
  for (const auto& k : keyed) out.emplace_back(std::get<2>(k), std::get<3>(k));
  return out;
}

// toml11 3.7 reports a syntax error's column as 1; its message draws a
// caret under the real one ("   |       ^--- here"). Column of the first
// caret, else `fallback`.
int caret_column(const std::string& what, int fallback) {
  std::istringstream lines(what);
  for (std::string line; std::getline(lines, line);) {
    const size_t bar = line.find(" | "), caret = line.find('^');
    if (bar == std::string::npos || caret == std::string::npos || caret < bar + 3) continue;
    if (line.find_first_not_of(' ', bar + 3) != caret) continue;
    return int(caret - (bar + 3)) + 1;
  }
  return fallback;
}

void parse_settings(const toml::value& table, PipelineSpec& spec, Diagnostics& d) {
  const std::string& file = spec.file;
  for (const auto& [key_ptr, v_ptr] : in_file_order(table)) {
    const std::string& key = *key_ptr;
    const toml::value& v = *v_ptr;
    const SourceLocation at = where(v, file);
    auto need = [&](bool ok, const char* type) {
      if (!ok) d.error(at, "", "[pipeline] " + key + " must be " + type + ", got " + toml_type_name(v));
      return ok;
    };
    if (key == "name") {
      if (need(v.is_string(), "a string")) spec.name = v.as_string();
    } else if (key == "dataset") {
      if (need(v.is_string(), "a string")) spec.dataset = v.as_string();
    } else if (key == "output") {
      if (need(v.is_string(), "a string")) spec.output = v.as_string();
    } else if (key == "seed") {
      if (need(v.is_integer(), "an integer")) {
        // toml11 reads an integer too large for 64 bits as the largest one.
        if (v.as_integer() == std::numeric_limits<std::int64_t>::max())
          d.error(at, "", "[pipeline] seed is too large (at most 9223372036854775806)");
        else if (v.as_integer() < 0) d.error(at, "", "[pipeline] seed must be >= 0");
        else spec.seed = static_cast<uint64_t>(v.as_integer());
      }
    } else if (key == "threads") {
      if (need(v.is_integer(), "an integer")) {
        if (v.as_integer() < 1 || v.as_integer() > 4096) d.error(at, "", "[pipeline] threads must be in [1, 4096]");
        else spec.threads = static_cast<int>(v.as_integer());
      }
    } else {
      d.error(key_where(v, key, file), "",
              "unknown key '" + key + "' in [pipeline] (known: name, seed, threads, dataset, output)");
    }
  }
}

void parse_stage(const std::string& id, const toml::value& table, PipelineSpec& spec, Diagnostics& d) {
  const std::string& file = spec.file;
  StageSpec s;
  s.id = id;
  s.where = where(table, file);
  if (!valid_id(id)) d.error(s.where, id, "stage id '" + id + "' must be letters, digits, '_' or '-' (no dots)");
  for (const auto& [key_ptr, v_ptr] : in_file_order(table)) {
    const std::string& key = *key_ptr;
    const toml::value& v = *v_ptr;
    const SourceLocation at = where(v, file);
    if (key == "plugin") {
      if (!v.is_string()) d.error(at, id, std::string("plugin must be a string, got ") + toml_type_name(v));
      else if (v.as_string().str.empty()) d.error(at, id, "plugin is empty; write plugin = \"<kind>.<name>\"");
      else s.plugin = v.as_string(), s.plugin_where = at;
    } else if (key == "inputs") {
      if (!v.is_table()) {
        d.error(at, id, "inputs must be a table such as inputs = { missions = \"read.missions\" }");
        continue;
      }
      for (const auto& [port_ptr, ref_ptr] : in_file_order(v)) {
        const std::string& port = *port_ptr;
        const toml::value& ref = *ref_ptr;
        const SourceLocation ref_at = where(ref, file);
        if (!ref.is_string()) {
          d.error(ref_at, id, "input '" + port + "' must be a string \"<stage>.<port>\"");
          s.unusable_inputs.push_back(port);
          continue;
        }
        const std::string text = ref.as_string();
        const size_t dot = text.rfind('.');
        if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) {
          d.error(ref_at, id, "input '" + port + "' = \"" + text + "\" is not of the form \"<stage>.<port>\"");
          s.unusable_inputs.push_back(port);
          continue;
        }
        s.inputs.push_back({port, text.substr(0, dot), text.substr(dot + 1), ref_at});
      }
    } else if (v.is_table() && table.as_table().count("plugin")) {
      // A parameter group, [stages.<id>.<group>] or <group> = { ... }: its
      // keys are the stage's parameters <group>.<key> (--set <id>.<group>.<key>=...).
      if (v.as_table().empty()) {
        RawParam p;  // an empty group names nothing the stage declares
        p.name = key;
        p.where = at;
        p.key_where = key_where(v, key, file);
        p.problem = "an empty parameter group";
        s.params.push_back(std::move(p));
      }
      for (const auto& [sub_ptr, sub_v_ptr] : in_file_order(v)) {
        RawParam p;
        p.name = key + "." + *sub_ptr;
        p.where = where(*sub_v_ptr, file);
        p.key_where = key_where(*sub_v_ptr, *sub_ptr, file);
        if (sub_v_ptr->is_table())
          p.problem = "a parameter group holds values, not tables";
        else
          p.value = to_param(*sub_v_ptr, p.problem);
        s.params.push_back(std::move(p));
      }
    } else {
      RawParam p;
      p.name = key;
      p.where = at;
      p.key_where = key_where(v, key, file);
      p.value = to_param(v, p.problem);
      s.params.push_back(std::move(p));
    }
  }
  if (s.plugin.empty() && !table.as_table().count("plugin")) {
    // [stages.a.b] makes stage 'a' holding a table 'b': a dot in the id.
    std::string sub;
    for (const auto& [key, v] : table.as_table())
      if (v.is_table()) sub = key;
    if (!sub.empty())
      d.error(s.where, id, "[stages." + id + "." + sub + "]: a stage id cannot hold a dot; write [stages." + id + "_" +
                               sub + "]");
    else
      d.error(s.where, id, "stage has no plugin = \"<kind>.<name>\"");
  }
  auto by_line = [](const auto& a, const auto& b) {
    return std::make_pair(a.where.line, a.where.column) < std::make_pair(b.where.line, b.where.column);
  };
  std::sort(s.inputs.begin(), s.inputs.end(), by_line);
  std::sort(s.params.begin(), s.params.end(), by_line);
  spec.stages.push_back(std::move(s));
}

PipelineSpec from_toml(const toml::value& root, const std::string& file, Diagnostics& d) {
  PipelineSpec spec;
  spec.file = file;
  for (const auto& [key_ptr, v_ptr] : in_file_order(root)) {
    const std::string& key = *key_ptr;
    const toml::value& v = *v_ptr;
    const SourceLocation at = where(v, file);
    if (key == "pipeline") {
      if (!v.is_table()) d.error(at, "", "[pipeline] must be a table");
      else parse_settings(v, spec, d);
    } else if (key == "stages") {
      if (!v.is_table()) {
        d.error(at, "", "stages must be tables [stages.<id>]");
        continue;
      }
      for (const auto& [id_ptr, table_ptr] : in_file_order(v)) {
        const std::string& id = *id_ptr;
        const toml::value& table = *table_ptr;
        if (!table.is_table()) d.error(where(table, file), id, "stages." + id + " must be a table [stages." + id + "]");
        else parse_stage(id, table, spec, d);
      }
    } else {
      d.error(at, "", "unknown top-level key '" + key + "' (expected [pipeline] and [stages.<id>])");
    }
  }
  // File order: messages, plans and ties in the topological order follow what the user wrote.
  std::sort(spec.stages.begin(), spec.stages.end(), [](const StageSpec& a, const StageSpec& b) {
    return std::make_pair(a.where.line, a.id) < std::make_pair(b.where.line, b.id);
  });
  if (spec.stages.empty() && d.errors.empty()) d.error({file, 0, 0}, "", "pipeline has no [stages.<id>] tables");
  return spec;
}

PipelineSpec parse_stream(std::istream& raw, const std::string& file, Diagnostics& d) {
  std::ostringstream buffer;
  buffer << raw.rdbuf();
  if (raw.bad()) throw Error("cannot read pipeline file '" + file + "'");
  const std::string text = buffer.str();
  check_toml_utf8(text, file);
  check_toml_nesting(text, file);
  std::istringstream in(text);
  toml::value root;
  try {
    root = toml::parse(in, file);
  } catch (const toml::syntax_error& e) {
    const auto& loc = e.location();
    throw Error("TOML syntax error: " + plain_syntax_message(first_line(e.what())))
        .at({file, static_cast<int>(loc.line()), caret_column(e.what(), static_cast<int>(loc.column()))});
  } catch (const toml::exception& e) {
    const auto& loc = e.location();
    throw Error("invalid TOML: " + first_line(e.what()))
        .at({file, static_cast<int>(loc.line()), static_cast<int>(loc.column())});
  } catch (const std::exception& e) {
    throw Error(std::string("invalid TOML: ") + first_line(e.what())).at({file, 0, 0});
  }
  return from_toml(root, file, d);
}

}  // namespace

const StageSpec* PipelineSpec::find(const std::string& id) const {
  for (const auto& s : stages)
    if (s.id == id) return &s;
  return nullptr;
}

PipelineSpec parse_pipeline_file(const std::string& path, Diagnostics& diagnostics) {
  std::error_code folder_ec;
  if (std::filesystem::is_directory(path, folder_ec))
    throw Error("'" + path + "' is a folder, not a pipeline file: give the .toml (e.g. pipelines/lista.toml)");
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    // A misspelt file name: suggest the nearest .toml beside where it was looked for.
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path want(path);
    const fs::path folder = want.has_parent_path() ? want.parent_path() : fs::path(".");
    std::vector<std::string> names;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
      if (it->path().extension() == ".toml") names.push_back(it->path().filename().string());
    std::sort(names.begin(), names.end());
    std::vector<std::string> close = similar_names(want.filename().string(), names);
    for (const auto& n : names)  // "octomap.toml" for "volumetric-octomap.toml"
      if (close.empty() && n.find(want.stem().string()) != std::string::npos) close.push_back(n);
    const std::string hint =
        close.empty() ? std::string()
                      : " (did you mean '" + (want.has_parent_path() ? (folder / close[0]).string() : close[0]) + "'?)";
    throw Error("cannot open pipeline file '" + path + "'" + hint);
  }
  return parse_stream(in, path, diagnostics);
}

PipelineSpec parse_pipeline_text(const std::string& text, const std::string& file_name, Diagnostics& diagnostics) {
  std::istringstream in(text);
  return parse_stream(in, file_name, diagnostics);
}

Override parse_override(const std::string& argument) {
  Override o;
  o.text = argument;
  const size_t eq = argument.find('=');
  const std::string target = argument.substr(0, eq);
  const size_t dot = target.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 == target.size())
    throw Error("--set '" + argument + "' is not of the form <stage>.<param>=<value>");
  auto trim = [](std::string s) {
    const auto b = s.find_first_not_of(" \t"), e = s.find_last_not_of(" \t");
    return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  };
  o.stage = trim(target.substr(0, dot));
  o.param = trim(target.substr(dot + 1));
  const std::string text = trim(argument.substr(eq + 1));
  // One value, one line: a newline would let the value open tables of its
  // own (--set 'a.b=1\n[stages.x]...'), which were silently dropped.
  if (text.find_first_of("\n\r") != std::string::npos)
    throw Error("--set '" + o.stage + "." + o.param + "=...': the value spans lines; give one TOML value on one line");
  check_toml_nesting(text, "--set " + o.stage + "." + o.param);
  try {
    check_toml_utf8(text, "--set");  // not UTF-8 (a Latin-1 path): no TOML value, the bare word below
    std::istringstream in("v = " + text);
    const toml::value root = toml::parse(in, "--set");
    o.value = to_param(root.as_table().at("v"), o.problem);
  } catch (const std::exception&) {
    o.value = ParamValue(text);  // a bare word (e.g. sparse) means the string
  }
  return o;
}

std::string shortened(std::string text, size_t most) {
  if (text.size() <= most) return text;
  const size_t total = text.size();
  text.resize(most);
  while (!text.empty() && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80) text.pop_back();  // whole UTF-8
  if (!text.empty() && static_cast<unsigned char>(text.back()) >= 0xC0) text.pop_back();
  return text + "... (" + std::to_string(total) + " characters, cut)";
}

std::string Diagnostic::str() const {
  std::string s;
  if (where.known()) s += where.str() + ": ";
  if (!stage.empty()) s += "stage '" + stage + "': ";
  return s + message;
}

void Diagnostics::sort_by_location() {
  for (auto* list : {&errors, &warnings}) {
    std::vector<std::string> files;
    for (const auto& d : *list)
      if (std::find(files.begin(), files.end(), d.where.file) == files.end()) files.push_back(d.where.file);
    auto key = [&files](const Diagnostic& d) {
      return std::make_tuple(std::find(files.begin(), files.end(), d.where.file) - files.begin(), d.where.line,
                             d.where.column);
    };
    std::stable_sort(list->begin(), list->end(),
                     [&key](const Diagnostic& a, const Diagnostic& b) { return key(a) < key(b); });
  }
}

Error Diagnostics::first_error() const {
  if (errors.empty()) return Error("no error");
  const auto& e = errors.front();
  Error err(e.message);
  err.at(e.where);
  if (!e.stage.empty()) err.in_stage(e.stage, "");
  return err;
}

}  // namespace lista::core
