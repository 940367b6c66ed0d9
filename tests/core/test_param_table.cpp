// ParamTable: one statement per parameter, bound to its config field.
#include <lista/param_table.hpp>
#include <lista/stage.hpp>

#include <gtest/gtest.h>

using namespace lista;

namespace {

struct Base {
  double weight = 0.5;
};

struct Config : Base {
  bool on = true;
  int count = 3;
  uint32_t seed = 7;
  float scale = 1.5f;
  std::string mode = "fast";
  std::vector<double> box = {1.0, 2.0};
  std::vector<std::string> names = {"a"};
};

ParamTable<Config> table() {
  ParamTable<Config> t;
  t.bind("weight", &Config::weight, "a field of the base").range(0.0, 1.0);
  t.bind("on", &Config::on, "a switch");
  t.bind("count", &Config::count, "an integer").range(1, 10);
  t.bind("seed", &Config::seed, "an unsigned integer");
  t.bind("scale", &Config::scale, "a float").unit("m");
  t.bind("mode", &Config::mode, "a choice").one_of({"fast", "exact"});
  t.bind("box", &Config::box, "a list of numbers");
  t.bind("names", &Config::names, "a list of names");
  return t;
}

}  // namespace

TEST(ParamTable, DefaultsAreTheFieldsOfADefaultConfig) {
  const std::vector<ParamSpec> specs = table().specs();
  ASSERT_EQ(specs.size(), 8u);
  EXPECT_EQ(specs[0].name, "weight");
  EXPECT_EQ(std::get<double>(specs[0].default_value), 0.5);
  EXPECT_EQ(specs[0].max, 1.0);
  EXPECT_EQ(specs[1].type, ParamType::boolean);
  EXPECT_EQ(std::get<int64_t>(specs[2].default_value), 3);
  EXPECT_EQ(specs[3].type, ParamType::integer);
  EXPECT_EQ(std::get<double>(specs[4].default_value), 1.5);
  EXPECT_EQ(specs[4].unit_label, "m");
  EXPECT_EQ(specs[5].choices, (std::vector<std::string>{"fast", "exact"}));
  EXPECT_EQ(specs[6].type, ParamType::real_list);
  EXPECT_EQ(specs[7].type, ParamType::text_list);
}

TEST(ParamTable, ReadFillsEveryBoundFieldFromTheRunsParams) {
  const ParamTable<Config> t = table();
  Params p = Params::defaults(t.specs());
  const Config d = t.read(p);
  EXPECT_EQ(d.mode, "fast");
  EXPECT_EQ(d.box, (std::vector<double>{1.0, 2.0}));
  p.set("weight", 0.25);
  p.set("on", false);
  p.set("count", int64_t{9});
  p.set("seed", int64_t{42});
  p.set("scale", 3.0);
  p.set("mode", std::string("exact"));
  p.set("names", std::vector<std::string>{"x", "y"});
  const Config c = t.read(p);
  EXPECT_EQ(c.weight, 0.25);
  EXPECT_FALSE(c.on);
  EXPECT_EQ(c.count, 9);
  EXPECT_EQ(c.seed, 42u);
  EXPECT_EQ(c.scale, 3.0f);
  EXPECT_EQ(c.mode, "exact");
  EXPECT_EQ(c.names, (std::vector<std::string>{"x", "y"}));
}

namespace {

enum class Speed { slow, fast };

struct Grouped {
  struct Noise {
    bool enabled = false;
    double sigma = 0.1;
    Speed speed = Speed::fast;
  } noise;
  Speed speed = Speed::slow;
};

ParamTable<Grouped> grouped() {
  ParamTable<Grouped> t;
  using N = Grouped::Noise;
  auto noise = t.group("noise", &Grouped::noise);
  noise.bind("enabled", &N::enabled, "a switch in a group");
  noise.bind("sigma", &N::sigma, "a number in a group").at_least(0.0);
  noise.choice("speed", &N::speed, {{"slow", Speed::slow}, {"fast", Speed::fast}}, "an enum");
  t.choice("speed", &Grouped::speed, {{"slow", Speed::slow}, {"fast", Speed::fast}}, "an enum");
  t.renamed("sigma", "noise.sigma");
  t.renamed("level", "noise.sigma", "noise.enabled", 0.0);
  return t;
}

}  // namespace

// A group's parameters fill a struct inside the config; an enum is a text
// parameter whose choices are its names, so validation checks it once.
TEST(ParamTable, GroupsFillNestedStructsAndChoicesFillEnums) {
  const ParamTable<Grouped> t = grouped();
  const std::vector<ParamSpec> specs = t.specs();
  ASSERT_EQ(specs.size(), 4u);
  EXPECT_EQ(specs[0].name, "noise.enabled");
  EXPECT_EQ(std::get<double>(specs[1].default_value), 0.1);
  EXPECT_EQ(specs[2].type, ParamType::text);
  EXPECT_EQ(std::get<std::string>(specs[2].default_value), "fast");
  EXPECT_EQ(specs[2].choices, (std::vector<std::string>{"slow", "fast"}));
  EXPECT_EQ(std::get<std::string>(specs[3].default_value), "slow");
  EXPECT_NE(specs[3].check(std::string("medium")), "");
  Params p = Params::defaults(specs);
  p.set("noise.enabled", true);
  p.set("noise.sigma", 0.5);
  p.set("noise.speed", std::string("slow"));
  p.set("speed", std::string("fast"));
  const Grouped g = t.read(p);
  EXPECT_TRUE(g.noise.enabled);
  EXPECT_EQ(g.noise.sigma, 0.5);
  EXPECT_EQ(g.noise.speed, Speed::slow);
  EXPECT_EQ(g.speed, Speed::fast);
}

// An old name fills the new parameter, or, for an old sentinel, the switch
// that spells it now; the warning names the new spelling and the reading.
TEST(ParamTable, RenamedParametersKeepTheirOldNamesForARelease) {
  const ParamTable<Grouped> t = grouped();
  ASSERT_EQ(t.renames().size(), 2u);
  const ParamRename& plain = t.renames()[0];
  EXPECT_EQ(plain.old_name, "sigma");
  const ParamAssignments as = plain.assignments(0.3);
  ASSERT_EQ(as.size(), 1u);
  EXPECT_EQ(as[0].first, "noise.sigma");
  EXPECT_EQ(std::get<double>(as[0].second), 0.3);
  EXPECT_EQ(plain.warning(0.3, as), "parameter 'sigma' is now 'noise.sigma' (the old name works until the next release)");

  const ParamRename& level = t.renames()[1];
  const ParamAssignments off = level.assignments(int64_t{0});  // an integer for the old real
  ASSERT_EQ(off.size(), 1u);
  EXPECT_EQ(off[0].first, "noise.enabled");
  EXPECT_FALSE(std::get<bool>(off[0].second));
  EXPECT_EQ(level.warning(int64_t{0}, off), "parameter 'level' is now 'noise.sigma' (the old name works until the next "
                                             "release); 0 reads as noise.enabled = false");
  const ParamAssignments on = level.assignments(0.2);
  ASSERT_EQ(on.size(), 2u);
  EXPECT_TRUE(std::get<bool>(on[0].second));
  EXPECT_EQ(on[1].first, "noise.sigma");
  EXPECT_EQ(std::get<double>(on[1].second), 0.2);
  EXPECT_THROW(level.assignments(std::string("loud")), Error);

  // A declaration that renames onto nothing, or keeps the old name, is refused.
  StageInfo info;
  info.name = "test.renamed";
  info.params = t.specs();
  info.renamed = t.renames();
  EXPECT_EQ(info.declaration_problem(), "");
  EXPECT_EQ(info.renamed_from("level"), &info.renamed[1]);
  info.renamed.push_back({"speed", "noise.speed", {}});
  EXPECT_EQ(info.declaration_problem(), "renames 'speed', which is still a parameter");
  info.renamed.back() = {"rate", "noise.rate", {}};
  EXPECT_EQ(info.declaration_problem(), "renames 'rate' to 'noise.rate', which is no parameter");
}
