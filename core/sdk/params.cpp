#include <lista/params.hpp>

#include <cmath>
#include <limits>
#include <sstream>

namespace lista {

const char* to_string(ParamType t) {
  switch (t) {
    case ParamType::boolean: return "bool";
    case ParamType::integer: return "int";
    case ParamType::real: return "float";
    case ParamType::text: return "string";
    case ParamType::real_list: return "float[]";
    case ParamType::text_list: return "string[]";
  }
  return "?";
}

namespace {

std::string number(double v) {
  std::ostringstream os;
  os.precision(15);
  os << v;
  std::string s = os.str();
  if (s.find_first_of(".eE") == std::string::npos && std::isfinite(v)) s += ".0";
  return s;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

ParamType type_of(const ParamValue& v) {
  switch (v.index()) {
    case 0: return ParamType::boolean;
    case 1: return ParamType::integer;
    case 2: return ParamType::real;
    case 3: return ParamType::text;
    case 4: return ParamType::real_list;
    default: return ParamType::text_list;
  }
}

ParamSpec make(std::string name, ParamType type, ParamValue def, std::string doc) {
  ParamSpec s;
  s.name = std::move(name);
  s.type = type;
  s.default_value = std::move(def);
  s.doc = std::move(doc);
  return s;
}

}  // namespace

std::string to_string(const ParamValue& v) {
  switch (v.index()) {
    case 0: return std::get<bool>(v) ? "true" : "false";
    case 1: return std::to_string(std::get<int64_t>(v));
    case 2: return number(std::get<double>(v));
    case 3: return quoted(std::get<std::string>(v));
    case 4: {
      std::string s = "[";
      for (double d : std::get<std::vector<double>>(v)) s += (s.size() > 1 ? ", " : "") + number(d);
      return s + "]";
    }
    default: {
      std::string s = "[";
      for (const auto& t : std::get<std::vector<std::string>>(v)) s += (s.size() > 1 ? ", " : "") + quoted(t);
      return s + "]";
    }
  }
}

ParamSpec ParamSpec::boolean(std::string n, bool d, std::string doc) { return make(std::move(n), ParamType::boolean, d, std::move(doc)); }
ParamSpec ParamSpec::integer(std::string n, int64_t d, std::string doc) { return make(std::move(n), ParamType::integer, d, std::move(doc)); }
ParamSpec ParamSpec::real(std::string n, double d, std::string doc) { return make(std::move(n), ParamType::real, d, std::move(doc)); }
ParamSpec ParamSpec::text(std::string n, std::string d, std::string doc) { return make(std::move(n), ParamType::text, std::move(d), std::move(doc)); }
ParamSpec ParamSpec::real_list(std::string n, std::vector<double> d, std::string doc) { return make(std::move(n), ParamType::real_list, std::move(d), std::move(doc)); }
ParamSpec ParamSpec::text_list(std::string n, std::vector<std::string> d, std::string doc) { return make(std::move(n), ParamType::text_list, std::move(d), std::move(doc)); }

std::string ParamSpec::check(const ParamValue& v) const {
  const ParamType got = type_of(v);
  const bool int_for_real = type == ParamType::real && got == ParamType::integer;
  if (got != type && !int_for_real)
    return std::string("must be ") + to_string(type) + ", got " + to_string(got) + " " + to_string(v);
  auto in_range = [&](double x) -> std::string {
    if (!std::isfinite(x) && (min || max)) return "must be finite, got " + number(x);
    if ((min && x < *min) || (max && x > *max))
      return "must be " + std::string(min && max ? "in " : "") + range_text() + ", got " + to_string(v);
    return {};
  };
  if (got == ParamType::integer) return in_range(double(std::get<int64_t>(v)));
  if (got == ParamType::real) return in_range(std::get<double>(v));
  if (got == ParamType::real_list)
    for (double x : std::get<std::vector<double>>(v))
      if (auto e = in_range(x); !e.empty()) return e;
  auto allowed = [&](const std::string& s) -> std::string {
    if (choices.empty()) return {};
    for (const auto& c : choices)
      if (c == s) return {};
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + quoted(c);
    return "must be one of " + list + ", got " + quoted(s);
  };
  if (got == ParamType::text) return allowed(std::get<std::string>(v));
  if (got == ParamType::text_list)
    for (const auto& s : std::get<std::vector<std::string>>(v))
      if (auto e = allowed(s); !e.empty()) return e;
  return {};
}

std::string ParamSpec::range_text() const {
  // An integer parameter's bounds read as integers, so the message matches what may be written.
  auto bound = [&](double x) {
    return type == ParamType::integer && std::isfinite(x) && x == std::floor(x) ? std::to_string(int64_t(x))
                                                                              : number(x);
  };
  if (min && max) return "[" + bound(*min) + ", " + bound(*max) + "]";
  if (min) return ">= " + bound(*min);
  if (max) return "<= " + bound(*max);
  return {};
}

ParamAssignments ParamRename::assignments(const ParamValue& v) const {
  return translate ? translate(v) : ParamAssignments{{new_name, v}};
}

std::string ParamRename::warning(const ParamValue& v, const ParamAssignments& as) const {
  std::string w = "parameter '" + old_name + "' is now '" + new_name + "' (the old name works until the next release)";
  if (!translate || as.empty()) return w;
  std::string reads;
  for (const auto& [name, value] : as) reads += (reads.empty() ? "" : ", ") + name + " = " + to_string(value);
  return w + "; " + to_string(v) + " reads as " + reads;
}

bool Params::is_set(const std::string& name) const {
  auto it = explicit_.find(name);
  return it != explicit_.end() && it->second;
}

SourceLocation Params::location(const std::string& name) const {
  auto it = locations_.find(name);
  return it == locations_.end() ? SourceLocation{} : it->second;
}

void Params::set(const std::string& name, ParamValue value, bool explicit_value, SourceLocation where) {
  values_[name] = std::move(value);
  explicit_[name] = explicit_value;
  locations_[name] = std::move(where);
}

const ParamValue& Params::value(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw Error("parameter '" + name + "' is not declared by this stage");
  return it->second;
}

Params Params::defaults(const std::vector<ParamSpec>& specs) {
  Params p;
  for (const auto& s : specs) p.set(s.name, s.default_value, false);
  return p;
}

namespace {
[[noreturn]] void wrong_type(const std::string& name, const char* want, const ParamValue& v) {
  throw Error("parameter '" + name + "' is " + to_string(v) + ", not a " + want);
}
template <class I>
I integral(const std::string& name, const ParamValue& v, const char* want) {
  if (v.index() != 1) wrong_type(name, want, v);
  const int64_t x = std::get<int64_t>(v);
  if (x < int64_t(std::numeric_limits<I>::min()) ||
      (x > 0 && uint64_t(x) > uint64_t(std::numeric_limits<I>::max())))
    throw Error("parameter '" + name + "' = " + std::to_string(x) + " does not fit a " + want);
  return static_cast<I>(x);
}
double real_value(const std::string& name, const ParamValue& v) {
  if (v.index() == 2) return std::get<double>(v);
  if (v.index() == 1) return double(std::get<int64_t>(v));
  wrong_type(name, "float", v);
}
}  // namespace

template <> bool Params::get<bool>(const std::string& n) const {
  const auto& v = value(n);
  if (v.index() != 0) wrong_type(n, "bool", v);
  return std::get<bool>(v);
}
template <> int64_t Params::get<int64_t>(const std::string& n) const { return integral<int64_t>(n, value(n), "int64"); }
template <> int Params::get<int>(const std::string& n) const { return integral<int>(n, value(n), "int"); }
template <> uint32_t Params::get<uint32_t>(const std::string& n) const { return integral<uint32_t>(n, value(n), "uint32"); }
template <> uint64_t Params::get<uint64_t>(const std::string& n) const { return integral<uint64_t>(n, value(n), "uint64"); }
template <> double Params::get<double>(const std::string& n) const { return real_value(n, value(n)); }
template <> float Params::get<float>(const std::string& n) const { return float(real_value(n, value(n))); }
template <> std::string Params::get<std::string>(const std::string& n) const {
  const auto& v = value(n);
  if (v.index() != 3) wrong_type(n, "string", v);
  return std::get<std::string>(v);
}
template <> std::vector<double> Params::get<std::vector<double>>(const std::string& n) const {
  const auto& v = value(n);
  if (v.index() != 4) wrong_type(n, "float list", v);
  return std::get<std::vector<double>>(v);
}
template <> std::vector<std::string> Params::get<std::vector<std::string>>(const std::string& n) const {
  const auto& v = value(n);
  if (v.index() != 5) wrong_type(n, "string list", v);
  return std::get<std::vector<std::string>>(v);
}

}  // namespace lista
