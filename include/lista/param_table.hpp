// Parameters declared once, bound to the config field they fill (as PDAL's
// args.add(name, help, member, default)): a stage's name, type, default,
// range, unit and doc are one statement, the default is the field's value in
// a default-constructed config, and the config read from a run's Params
// cannot disagree with `lista-run --describe`.
//
//   struct Config { double resolution = 0.05; std::string mode = "fast"; };
//   const ParamTable<Config>& table() {
//     static const ParamTable<Config> t = [] {
//       ParamTable<Config> t;
//       t.bind("resolution", &Config::resolution, "voxel edge").range(0.005, 5).unit("m");
//       t.bind("mode", &Config::mode, "how").one_of({"fast", "exact"});
//       return t;
//     }();
//     return t;
//   }
//   info.params = table().specs();          // what --describe and validation see
//   const Config c = table().read(params);  // in the stage's constructor
#pragma once

#include <lista/params.hpp>

#include <deque>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace lista {

template <class Config>
class ParamTable {
 public:
  // Declares parameter `name` filling `field` (of Config or a base of it);
  // the returned spec takes the range, unit and choices. Field types: bool,
  // any integer, float, double, std::string, std::vector<double>,
  // std::vector<std::string>.
  template <class T, class Owner>
  ParamSpec& bind(std::string name, T Owner::*member, std::string doc) {
    static_assert(std::is_base_of_v<Owner, Config>, "ParamTable::bind: a field of another config");
    T Config::*field = member;
    const Config defaults{};
    const T& def = defaults.*field;
    ParamSpec spec;
    if constexpr (std::is_same_v<T, bool>) {
      spec = ParamSpec::boolean(name, def, std::move(doc));
    } else if constexpr (std::is_integral_v<T>) {
      spec = ParamSpec::integer(name, static_cast<int64_t>(def), std::move(doc));
    } else if constexpr (std::is_floating_point_v<T>) {
      spec = ParamSpec::real(name, static_cast<double>(def), std::move(doc));
    } else if constexpr (std::is_same_v<T, std::string>) {
      spec = ParamSpec::text(name, def, std::move(doc));
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      spec = ParamSpec::real_list(name, def, std::move(doc));
    } else {
      static_assert(std::is_same_v<T, std::vector<std::string>>, "ParamTable::bind: no parameter type for this field");
      spec = ParamSpec::text_list(name, def, std::move(doc));
    }
    entries_.push_back({std::move(spec), [field, name](Config& c, const Params& p) { c.*field = p.get<T>(name); }});
    return entries_.back().spec;
  }

  std::vector<ParamSpec> specs() const {
    std::vector<ParamSpec> out;
    for (const auto& e : entries_) out.push_back(e.spec);
    return out;
  }

  // A default config with every bound field taken from `p`.
  Config read(const Params& p) const {
    Config c{};
    for (const auto& e : entries_) e.fill(c, p);
    return c;
  }

 private:
  struct Entry {
    ParamSpec spec;
    std::function<void(Config&, const Params&)> fill;
  };
  std::deque<Entry> entries_;  // stable references for the chained setters
};

}  // namespace lista
