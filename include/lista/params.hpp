// Parameters: declared once per stage (name, type, default, range, doc) and
// used for validation, `lista-run --describe`, docs and the run itself.
//
//   ParamSpec::real("resolution", 0.05, "voxel edge length").range(0.005, 5.0).unit("m")
//   ParamSpec::text("solver", "dense", "linear solver").one_of({"dense", "sparse"})
#pragma once

#include <lista/error.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace lista {

enum class ParamType { boolean, integer, real, text, real_list, text_list };
const char* to_string(ParamType t);  // "bool", "int", "float", "string", "float[]", "string[]"

using ParamValue = std::variant<bool, int64_t, double, std::string, std::vector<double>,
                                std::vector<std::string>>;
std::string to_string(const ParamValue& v);  // TOML spelling: 0.05, "dense", [1.0, 2.0]

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::real;
  ParamValue default_value = 0.0;
  std::optional<double> min, max;     // inclusive bounds for numbers (each element of lists)
  std::vector<std::string> choices;   // allowed values for text
  std::string doc;
  std::string unit_label;             // e.g. "m", "deg"; empty if none

  static ParamSpec boolean(std::string name, bool def, std::string doc);
  static ParamSpec integer(std::string name, int64_t def, std::string doc);
  static ParamSpec real(std::string name, double def, std::string doc);
  static ParamSpec text(std::string name, std::string def, std::string doc);
  static ParamSpec real_list(std::string name, std::vector<double> def, std::string doc);
  static ParamSpec text_list(std::string name, std::vector<std::string> def, std::string doc);

  ParamSpec& range(double lo, double hi) { min = lo; max = hi; return *this; }
  ParamSpec& at_least(double lo) { min = lo; return *this; }
  ParamSpec& at_most(double hi) { max = hi; return *this; }
  ParamSpec& one_of(std::vector<std::string> values) { choices = std::move(values); return *this; }
  ParamSpec& unit(std::string u) { unit_label = std::move(u); return *this; }

  // Empty if `v` is acceptable, else what is wrong ("must be in [0, 1], got 3").
  // An integer is accepted where a real is declared (converted).
  std::string check(const ParamValue& v) const;

  // The bounds as written in TOML for this type ("[1, 64]" for an integer,
  // "[0.0, 1.0]" for a float, ">= 0.5"); empty if unbounded.
  std::string range_text() const;
};

// Values of parameters by name, in the order they are set.
using ParamAssignments = std::vector<std::pair<std::string, ParamValue>>;

// A parameter renamed (moved into a group, or a sentinel value made an
// explicit switch): a pipeline or --set that writes the old name still works
// for one release and is told the new spelling.
struct ParamRename {
  std::string old_name, new_name;
  // The new parameters' values for an old value that they spell otherwise
  // (an old "0 = off" as `enabled = false`); empty: the value is new_name's.
  // Throws lista::Error for a value of the wrong type.
  std::function<ParamAssignments(const ParamValue&)> translate;

  // What writing `old_name = v` sets.
  ParamAssignments assignments(const ParamValue& v) const;
  // "parameter 'a' is now 'g.a' (the old name works until the next release)",
  // and for a translated value `v` what it reads as (`as`, when given).
  std::string warning(const ParamValue& v, const ParamAssignments& as) const;
};

// The resolved parameters of one stage instance: every declared parameter has
// a value (the default where the pipeline is silent).
class Params {
 public:
  // Typed access: bool, int, int64_t, uint32_t, uint64_t, double, float,
  // std::string, std::vector<double>, std::vector<std::string>. Throws
  // lista::Error for an undeclared name or a type that does not fit.
  template <class T>
  T get(const std::string& name) const;

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  // True if the pipeline (or a --set override) gave the value explicitly.
  bool is_set(const std::string& name) const;
  // Where the value was written; unknown for defaults.
  SourceLocation location(const std::string& name) const;

  void set(const std::string& name, ParamValue value, bool explicit_value = true,
           SourceLocation where = {});
  const ParamValue& value(const std::string& name) const;
  const std::map<std::string, ParamValue>& values() const { return values_; }

  // Parameters with every default of `specs`.
  static Params defaults(const std::vector<ParamSpec>& specs);

 private:
  std::map<std::string, ParamValue> values_;
  std::map<std::string, SourceLocation> locations_;
  std::map<std::string, bool> explicit_;
};

}  // namespace lista
