// ParamTable: one statement per parameter, bound to its config field.
#include <lista/param_table.hpp>

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
