// Parameters declared once, bound to the config field they fill (as PDAL's
// args.add(name, help, member, default)): a stage's name, type, default,
// range, unit and doc are one statement, the default is the field's value in
// a default-constructed config, and the config read from a run's Params
// cannot disagree with `lista-run --describe`.
//
//   struct Config { double resolution = 0.05; std::string mode = "fast"; };
//   const ParamTable<Config>& table() {
//     return ParamTable<Config>::once([](ParamTable<Config>& t) {
//       t.bind("resolution", &Config::resolution, "voxel edge").range(0.005, 5).unit("m");
//       t.bind("mode", &Config::mode, "how").one_of({"fast", "exact"});
//     });
//   }
//   info.params = table().specs();          // what --describe and validation see
//   info.renamed = table().renames();       // old names still accepted
//   const Config c = table().read(params);  // in the stage's constructor
//
// A group's parameters fill a struct inside the config (group()), enums are
// declared with their names (choice()), and renamed() keeps a parameter's
// old name working for one release.
#pragma once

#include <lista/params.hpp>

#include <deque>
#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace lista {

// A field of a struct inside the config (a parameter group's).
template <class Owner, class Group, class T>
struct NestedField {
  Group Owner::*group;
  T Group::*member;
};

// The type a field (a member pointer or a NestedField) holds.
template <class Field>
struct FieldType;
template <class T, class Owner>
struct FieldType<T Owner::*> {
  using type = T;
};
template <class Owner, class Group, class T>
struct FieldType<NestedField<Owner, Group, T>> {
  using type = T;
};

template <class Config>
class ParamTable {
 public:
  // Declares parameter `name` filling `field` (of Config or a base of it);
  // the returned spec takes the range, unit and choices. Field types: bool,
  // any integer, float, double, std::string, std::vector<double>,
  // std::vector<std::string>.
  template <class T, class Owner>
  ParamSpec& bind(std::string name, T Owner::*member, std::string doc) {
    return add<T>(std::move(name), field_of(member), std::move(doc));
  }

  // Declares a text parameter whose choices are the names in `names`,
  // filling `field` (an enum, usually) with the value of the name chosen:
  // validation checks the choice once and the stage gets no text to check.
  template <class Field>
  ParamSpec& choice(std::string name, Field field,
                    std::vector<std::pair<std::string, typename FieldType<Field>::type>> names, std::string doc) {
    const auto at = field_of(field);
    Config defaults{};
    std::string def;
    std::vector<std::string> choices;
    for (const auto& [text, value] : names) {
      choices.push_back(text);
      if (def.empty() && value == at(defaults)) def = text;
    }
    ParamSpec spec = ParamSpec::text(name, def, std::move(doc)).one_of(std::move(choices));
    entries_.push_back({std::move(spec), [at, name, names](Config& c, const Params& p) {
      const std::string chosen = p.get<std::string>(name);
      for (const auto& [text, value] : names)
        if (text == chosen) return void(at(c) = value);
      throw Error("parameter '" + name + "' = \"" + chosen + "\" is none of its choices");  // Params not validated
    }});
    return entries_.back().spec;
  }

  // The parameters `<name>.<key>` of a group, filling the fields of the
  // struct `member` inside the config, so that the struct reads as the TOML:
  //   auto scans = t.group("scans", &Config::scans);
  //   scans.bind("points", &Scans::points, "points kept per scan");
  template <class G>
  struct Group {
    ParamTable& table;
    std::string prefix;
    G Config::*member;
    template <class T>
    ParamSpec& bind(const std::string& key, T G::*field, std::string doc) {
      return table.bind(prefix + key, NestedField<Config, G, T>{member, field}, std::move(doc));
    }
    template <class T>
    ParamSpec& choice(const std::string& key, T G::*field, std::vector<std::pair<std::string, T>> names,
                      std::string doc) {
      return table.choice(prefix + key, NestedField<Config, G, T>{member, field}, std::move(names), std::move(doc));
    }
  };
  template <class G, class Owner>
  Group<G> group(const std::string& name, G Owner::*member) {
    static_assert(std::is_base_of_v<Owner, Config>, "ParamTable::group: a field of another config");
    return {*this, name + ".", member};
  }

  // `old_name` is now `new_name`: a pipeline that writes the old name runs
  // for one release more, with a warning naming the new spelling.
  void renamed(std::string old_name, std::string new_name) {
    renames_.push_back({std::move(old_name), std::move(new_name), {}});
  }
  // The same for a number whose old value the new parameters spell
  // otherwise: `how` gives their values for it (an old sentinel 0 as
  // {{"gate.enabled", false}}).
  void renamed(std::string old_name, std::string new_name, std::function<ParamAssignments(double)> how) {
    auto translate = [how, old_name](const ParamValue& v) {
      if (std::string why = ParamSpec::real(old_name, 0.0, "").check(v); !why.empty())
        throw Error("parameter '" + old_name + "' " + why);
      return how(v.index() == 1 ? double(std::get<int64_t>(v)) : std::get<double>(v));
    };
    renames_.push_back({std::move(old_name), std::move(new_name), std::move(translate)});
  }
  // The same for an old "`off` = off": that value reads as `toggle = false`,
  // any other as `toggle = true` and new_name = the value.
  void renamed(std::string old_name, std::string new_name, std::string toggle, double off) {
    renamed(std::move(old_name), new_name, [new_name, toggle, off](double v) {
      return v == off ? ParamAssignments{{toggle, false}} : ParamAssignments{{toggle, true}, {new_name, v}};
    });
  }

  // The table `declare` fills, made once, on first use (the example above).
  template <class Declare>
  static const ParamTable& once(Declare declare) {
    static const ParamTable table = [&] {
      ParamTable t;
      declare(t);
      return t;
    }();
    return table;
  }

  std::vector<ParamSpec> specs() const {
    std::vector<ParamSpec> out;
    for (const auto& e : entries_) out.push_back(e.spec);
    return out;
  }
  const std::vector<ParamRename>& renames() const { return renames_; }

  // A default config with every bound field taken from `p`.
  Config read(const Params& p) const {
    Config c{};
    for (const auto& e : entries_) e.fill(c, p);
    return c;
  }

 private:
  // A group's field (Group::bind).
  template <class T, class Owner, class Inner>
  ParamSpec& bind(std::string name, NestedField<Owner, Inner, T> nested, std::string doc) {
    return add<T>(std::move(name), field_of(nested), std::move(doc));
  }

  template <class T, class Owner>
  static auto field_of(T Owner::*member) {
    static_assert(std::is_base_of_v<Owner, Config>, "ParamTable: a field of another config");
    T Config::*field = member;
    return [field](Config& c) -> T& { return c.*field; };
  }
  template <class T, class Owner, class Inner>
  static auto field_of(NestedField<Owner, Inner, T> nested) {
    static_assert(std::is_base_of_v<Owner, Config>, "ParamTable: a field of another config");
    Inner Config::*group = nested.group;
    T Inner::*member = nested.member;
    return [group, member](Config& c) -> T& { return (c.*group).*member; };
  }

  template <class T, class At>
  ParamSpec& add(std::string name, At at, std::string doc) {
    Config defaults{};
    const T& def = at(defaults);
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
    entries_.push_back({std::move(spec), [at, name](Config& c, const Params& p) { at(c) = p.get<T>(name); }});
    return entries_.back().spec;
  }

  struct Entry {
    ParamSpec spec;
    std::function<void(Config&, const Params&)> fill;
  };
  std::deque<Entry> entries_;  // stable references for the chained setters
  std::vector<ParamRename> renames_;
};

}  // namespace lista
