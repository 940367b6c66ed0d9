// Pipeline parsing and validation: every error class with its exact line.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <tuple>

using namespace lista::core;
using lista_test::plan_of;

namespace {

// The errors of `toml`, as "line: message" strings.
std::vector<Diagnostic> errors_of(const std::string& toml, const std::vector<std::string>& sets = {}) {
  Diagnostics d;
  plan_of(toml, d, sets);
  return d.errors;
}

// Exactly one error, at `line`, whose message contains `text`.
void expect_one_error(const std::string& toml, int line, const std::string& text,
                      const std::vector<std::string>& sets = {}) {
  const auto errors = errors_of(toml, sets);
  ASSERT_EQ(errors.size(), 1u) << (errors.empty() ? "no error" : errors[0].str() + " ... and more");
  EXPECT_EQ(errors[0].where.file, "p.toml");
  EXPECT_EQ(errors[0].where.line, line) << errors[0].str();
  EXPECT_NE(errors[0].message.find(text), std::string::npos) << errors[0].str();
}

const std::string source = "[stages.src]\nplugin = \"test.source\"\n";  // lines 1-2
const std::string chain = source +
                          "[stages.pts]\n"                               // 3
                          "plugin = \"test.to_points\"\n"                // 4
                          "inputs = { missions = \"src.missions\" }\n"   // 5
                          "[stages.sink]\n"                              // 6
                          "plugin = \"test.sink\"\n"                     // 7
                          "inputs = { points = \"pts.points\" }\n";      // 8

}  // namespace

TEST(Pipeline, ValidChainPlansInOrderWithResolvedParams) {
  Diagnostics d;
  const Plan plan = plan_of("[pipeline]\nname = \"ok\"\nseed = 3\n" + chain + "[stages.src2]\nplugin=\"test.source\"\n", d);
  ASSERT_TRUE(d.ok()) << d.errors[0].str();
  ASSERT_EQ(plan.stages.size(), 4u);
  EXPECT_EQ(plan.stages[0].id, "src");
  EXPECT_EQ(plan.stages[1].id, "pts");
  EXPECT_EQ(plan.stages[2].id, "sink");
  EXPECT_EQ(plan.stages[3].id, "src2");
  EXPECT_EQ(plan.stages[2].level, 2);
  EXPECT_EQ(plan.levels, 3);
  EXPECT_EQ(plan.stages[0].params.get<int>("count"), 100);  // default
  EXPECT_FALSE(plan.stages[0].params.is_set("count"));
  EXPECT_EQ(*plan.spec.seed, 3u);
  ASSERT_EQ(d.warnings.size(), 1u);  // src2.missions unused
  EXPECT_NE(d.warnings[0].message.find("'missions'"), std::string::npos);
  EXPECT_EQ(d.warnings[0].stage, "src2");
}

TEST(Pipeline, ParamsFromFileAndIntegerForReal) {
  Diagnostics d;
  const Plan plan = plan_of(chain + "[stages.src.x]\n", d);  // nested table is not a param value
  EXPECT_FALSE(d.ok());
  Diagnostics d2;
  const Plan p2 = plan_of("[stages.src]\nplugin = \"test.source\"\ncount = 7\nscale = 2\nweights = [1, 2.5]\n"
                          "tags = [\"a\"]\nmode = \"exact\"\nverbose = true\n", d2);
  ASSERT_TRUE(d2.ok()) << d2.errors[0].str();
  const auto& params = p2.stages[0].params;
  EXPECT_EQ(params.get<int>("count"), 7);
  EXPECT_DOUBLE_EQ(params.get<double>("scale"), 2.0);
  EXPECT_EQ(params.value("scale").index(), 2u);  // stored as a real
  EXPECT_EQ(params.get<std::vector<double>>("weights"), (std::vector<double>{1.0, 2.5}));
  EXPECT_EQ(params.get<std::string>("mode"), "exact");
  EXPECT_TRUE(params.get<bool>("verbose"));
  EXPECT_EQ(params.location("count").line, 3);
}

TEST(Pipeline, UnknownPluginWithSuggestion) {
  expect_one_error("[stages.a]\n\nplugin = \"test.sourse\"\n", 3, "did you mean 'test.source'");
}

TEST(Pipeline, StageWithoutPlugin) { expect_one_error("[stages.a]\ncount = 1\n", 1, "has no plugin"); }
TEST(Pipeline, EmptyPluginIsAnError) { expect_one_error("[stages.a]\nplugin = \"\"\n", 2, "plugin is empty"); }

TEST(Pipeline, UnknownParameterWithSuggestion) {
  expect_one_error(source + "cuont = 5\n", 3, "did you mean 'count'");
}

TEST(Pipeline, WrongParameterType) {
  expect_one_error(source + "count = 1.5\n", 3, "must be int");
  expect_one_error(source + "verbose = \"yes\"\n", 3, "must be bool");
  expect_one_error(source + "tags = [1, 2]\n", 3, "must be string[]");
  expect_one_error(source + "tags = [1, \"a\"]\n", 3, "only numbers or only strings");
}

TEST(Pipeline, OutOfRangeAndChoices) {
  expect_one_error(source + "\nscale = 5000.0\n", 4, "[0.001, 1000");
  // An integer's bounds read as integers, as they would be written.
  expect_one_error(source + "missions = 0\n", 3, "must be in [1, 100], got 0");
  expect_one_error(source + "weights = [1.0, -2.0]\n", 3, ">= 0");
  expect_one_error(source + "mode = \"slow\"\n", 3, "must be one of");
}

TEST(Pipeline, MissingRequiredInput) {
  // test.join requires a and b; c is optional.
  expect_one_error(source + "[stages.j]\nplugin = \"test.join\"\ninputs = { a = \"src.missions\" }\n", 3,
                   "required input 'b'");
}

TEST(Pipeline, UnknownInputPort) {
  expect_one_error(source + "[stages.p]\nplugin = \"test.passthrough\"\n"
                            "inputs = { missions = \"src.missions\", mission = \"src.missions\" }\n",
                   5, "unknown input port 'mission'");
}

TEST(Pipeline, ReferenceToUnknownStageOrPort) {
  expect_one_error(source + "[stages.p]\nplugin = \"test.passthrough\"\ninputs = { missions = \"srx.missions\" }\n",
                   5, "unknown stage 'srx' (did you mean 'src'?)");
  expect_one_error(source + "[stages.p]\nplugin = \"test.passthrough\"\ninputs = { missions = \"src.mission\" }\n",
                   5, "has no output 'mission' (did you mean 'missions'?)");
  expect_one_error(source + "[stages.p]\nplugin = \"test.passthrough\"\ninputs = { missions = \"src\" }\n", 5,
                   "not of the form");
}

TEST(Pipeline, PortTypeMismatch) {
  expect_one_error(source + "[stages.s]\nplugin = \"test.sink\"\n\ninputs = { points = \"src.missions\" }\n", 6,
                   "expects 'points' but src.missions is 'missions'");
}

TEST(Pipeline, CycleIsNamed) {
  const std::string toml = source +
                           "[stages.a]\nplugin = \"test.passthrough\"\ninputs = { missions = \"c.missions\" }\n"  // 3-5
                           "[stages.b]\nplugin = \"test.passthrough\"\ninputs = { missions = \"a.missions\" }\n"  // 6-8
                           "[stages.c]\nplugin = \"test.passthrough\"\ninputs = { missions = \"b.missions\" }\n"; // 9-11
  const auto errors = errors_of(toml);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_NE(errors[0].message.find("cycle"), std::string::npos) << errors[0].str();
  for (const char* id : {"a ->", "b ->", "c ->"}) EXPECT_NE(errors[0].message.find(id), std::string::npos) << errors[0].str();
  EXPECT_TRUE(errors[0].where.line == 3 || errors[0].where.line == 6 || errors[0].where.line == 9);
  expect_one_error(source + "[stages.a]\nplugin = \"test.passthrough\"\ninputs = { missions = \"a.missions\" }\n", 5,
                   "cycle: a -> a");
}

TEST(Pipeline, PipelineSettingsAreChecked) {
  expect_one_error("[pipeline]\nseed = \"x\"\n" + source, 2, "seed must be an integer");
  expect_one_error("[pipeline]\nthreads = 0\n" + source, 2, "threads must be in");
  expect_one_error("[pipeline]\nseed = 99999999999999999999\n" + source, 2, "seed is too large");
  expect_one_error("[pipeline]\nnmae = \"x\"\n" + source, 2, "unknown key 'nmae'");
  // A 1 MB key is quoted, not echoed whole.
  const auto huge = errors_of("[pipeline]\n" + std::string(1 << 20, 'k') + " = 1\n" + source);
  ASSERT_EQ(huge.size(), 1u);
  EXPECT_LT(huge[0].str().size(), 600u);
  EXPECT_NE(huge[0].message.find("characters, cut)"), std::string::npos) << huge[0].message.substr(0, 100);
  expect_one_error(source + "[other]\n", 3, "unknown top-level key");
  expect_one_error("stages = 3\n", 1, "stages must be tables");
  expect_one_error("[stages.\"a.b\"]\nplugin = \"test.source\"\n", 1, "no dots");
}

TEST(Pipeline, UnknownKeysPointAtTheKeyWrongValuesAtTheValue) {
  auto only = [](const std::string& toml) {
    const auto errors = errors_of(toml);
    EXPECT_EQ(errors.size(), 1u);
    return errors.empty() ? Diagnostic{} : errors[0];
  };
  EXPECT_EQ(only("[pipeline]\n  nmae = \"x\"\n" + source).where.column, 3);
  const Diagnostic unknown = only(source + "cout   = 5\n");
  EXPECT_EQ(unknown.where.line, 3);
  EXPECT_EQ(unknown.where.column, 1);
  EXPECT_EQ(only(source + "\"cout\" = 5\n").where.column, 1);  // a quoted key: at its quote
  const Diagnostic wrong = only(source + "missions = 0\n");
  EXPECT_EQ(wrong.where.line, 3);
  EXPECT_EQ(wrong.where.column, 12);
}

TEST(Pipeline, AllErrorsAreCollected) {
  const auto errors = errors_of(source + "cuont = 1\nscale = -1.0\n[stages.x]\nplugin = \"nope.nope\"\n");
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_EQ(errors[0].where.line, 3);
  EXPECT_EQ(errors[1].where.line, 4);
  EXPECT_EQ(errors[2].where.line, 6);
}

// toml11 keeps tables in a hash map; messages still follow the file.
TEST(Pipeline, ErrorsComeInFileOrder) {
  const auto errors = errors_of("[pipeline]\nzz = 1\naa = 2\nthreads = \"x\"\nmm = 3\n"
                                "[stages.b]\nplugin = \"nope.b\"\n[stages.a]\nplugin = \"nope.a\"\n");
  ASSERT_EQ(errors.size(), 6u);
  for (size_t i = 1; i < errors.size(); ++i)
    EXPECT_LT(errors[i - 1].where.line, errors[i].where.line) << errors[i - 1].message << " / " << errors[i].message;
}

TEST(Pipeline, SyntaxErrorHasLineAndColumn) {
  Diagnostics d;
  try {
    parse_pipeline_text("[pipeline]\nname = \"x\"\nseed = = 3\n", "p.toml", d);
    FAIL() << "no syntax error";
  } catch (const lista::Error& e) {
    EXPECT_EQ(e.location().file, "p.toml");
    EXPECT_EQ(e.location().line, 3);
    EXPECT_EQ(e.location().column, 8) << "the second =";
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line: " << e.what();
  }
}

// Thousands of nested arrays or inline tables overflowed toml11's recursion
// (SIGSEGV); brackets in strings and comments do not count, and a folder
// is no pipeline.
TEST(Pipeline, DeepNestingIsRefusedBeforeTheParserRecurses) {
  auto error_of = [](const std::string& text) -> std::string {
    Diagnostics d;
    try {
      parse_pipeline_text(text, "p.toml", d);
    } catch (const lista::Error& e) {
      return std::to_string(e.location().line) + ":" + std::to_string(e.location().column) + " " + e.what();
    }
    return "";
  };
  const std::string arrays =
      "[pipeline]\nname = \"x\"\nseed = " + std::string(7000, '[') + std::string(7000, ']') + "\n";
  EXPECT_NE(error_of(arrays).find("3:72 "), std::string::npos) << error_of(arrays);
  EXPECT_NE(error_of(arrays).find("nested more than 64 deep"), std::string::npos);
  std::string tables = "x = ";
  for (int i = 0; i < 10000; ++i) tables += "{a = ";
  tables += "1" + std::string(10000, '}');
  EXPECT_NE(error_of(tables).find("nested more than 64 deep"), std::string::npos);
  // 64 levels pass the check, and brackets inside strings, multi-line
  // strings and comments are text.
  const std::string quoted = source + "s = \"" + std::string(100, '[') + "\"\nt = '''\n" + std::string(100, '{') +
                             "\n'''\n# " + std::string(100, '[') + "\nu = " + std::string(64, '[') +
                             std::string(64, ']') + "\n";
  EXPECT_EQ(error_of(quoted).find("nested"), std::string::npos) << error_of(quoted);
  try {
    parse_override("src.count=" + std::string(5000, '[') + std::string(5000, ']'));
    ADD_FAILURE() << "a deep --set value was accepted";
  } catch (const lista::Error& e) {
    EXPECT_NE(std::string(e.what()).find("--set src.count"), std::string::npos) << e.what();
  }
  Diagnostics d;
  EXPECT_THROW(parse_pipeline_file(std::filesystem::temp_directory_path().string(), d), lista::Error);
}

// toml11 3.7 read past its buffer on a literal string holding bytes that
// are not UTF-8 (found by fuzz_pipeline): such a file is refused first.
TEST(Pipeline, BytesThatAreNotUtf8AreRefusedWithTheirPlace) {
  Diagnostics d;
  auto refused_at = [&](const std::string& text, int line, int column, const std::string& message) {
    try {
      parse_pipeline_text(text, "p.toml", d);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const lista::Error& e) {
      EXPECT_EQ(e.location().line, line);
      EXPECT_EQ(e.location().column, column);
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  refused_at("[pipeline]\nname = ['a', 'b\xb9\xb9']\n", 2, 16, "byte 0xB9 is not UTF-8");
  EXPECT_NO_THROW(parse_pipeline_text("# caf\xc3\xa9\n[pipeline]\nname = 'd\xc3\xa9j\xc3\xa0'\n", "p.toml", d));
  // Well-formed in shape but not UTF-8 (past U+10FFFF, a surrogate, overlong
  // forms) inside a multi-line string: toml11 read past its buffer too.
  for (const char* bad : {"\xf4\x91\x9e\x92", "\xed\xa0\x80", "\xe0\x80\x80", "\xf0\x80\x80\x80"})
    refused_at(std::string("[pipeline]\nname = '''a") + bad + "'''\n", 2, 12, "is not UTF-8");
  EXPECT_NO_THROW(parse_pipeline_text("[pipeline]\nname = '''\xf4\x8f\xbf\xbf \xed\x9f\xbf \xe0\xa0\x80'''\n", "p.toml", d));
  // A --set value that is not UTF-8 is the bare word it always was.
  const Override o = parse_override("src.path=/data/caf\xe9");
  ASSERT_TRUE(o.value.has_value());
  EXPECT_EQ(std::get<std::string>(*o.value), "/data/caf\xe9");
}

TEST(Overrides, ParsedAsTomlOrBareString) {
  auto o = parse_override("src.count=12");
  EXPECT_EQ(o.stage, "src");
  EXPECT_EQ(o.param, "count");
  EXPECT_EQ(std::get<int64_t>(*o.value), 12);
  EXPECT_EQ(std::get<std::string>(*parse_override("src.mode=exact").value), "exact");
  EXPECT_EQ(std::get<std::string>(*parse_override("src.mode=\"exact\"").value), "exact");
  EXPECT_DOUBLE_EQ(std::get<double>(*parse_override("src.scale=0.5").value), 0.5);
  EXPECT_TRUE(std::get<bool>(*parse_override("src.verbose=true").value));
  EXPECT_EQ(std::get<std::vector<double>>(*parse_override("src.weights=[1, 2]").value).size(), 2u);
  EXPECT_THROW(parse_override("count=3"), lista::Error);
  EXPECT_THROW(parse_override("src.count"), lista::Error);
  EXPECT_THROW(parse_override(".count=3"), lista::Error);
  // Numbers toml11 would clamp to the type's limit are not what was written.
  EXPECT_EQ(parse_override("src.scale=1e400").problem, "the number is too large for a 64-bit value");
  EXPECT_EQ(parse_override("src.count=99999999999999999999").problem, "the number is too large for a 64-bit value");
  EXPECT_TRUE(parse_override("src.scale=1e300").problem.empty());
  // A value that opens a table of its own on a new line is refused, not half-taken.
  try {
    parse_override("src.count=3\n[stages.evil]\nplugin = \"io.missions\"");
    ADD_FAILURE() << "a multi-line value was accepted";
  } catch (const lista::Error& e) {
    EXPECT_NE(std::string(e.what()).find("--set 'src.count=...': the value spans lines"), std::string::npos) << e.what();
  }
}

TEST(Overrides, ApplyAfterFileAndAreValidated) {
  Diagnostics d;
  const Plan plan = plan_of(source + "count = 5\n", d, {"src.count=9", "src.mode=exact"});
  ASSERT_TRUE(d.ok()) << d.errors[0].str();
  EXPECT_EQ(plan.stages[0].params.get<int>("count"), 9);
  EXPECT_EQ(plan.stages[0].params.get<std::string>("mode"), "exact");
  EXPECT_NE(plan.resolved_toml().find("count = 9"), std::string::npos);
  expect_one_error(source, 1, "must be in", {"src.missions=1000"});
  expect_one_error(source, 1, "unknown parameter 'cout'", {"src.cout=1"});
  expect_one_error(source, 0, "no stage 'srx'", {"srx.count=1"});
  expect_one_error(source, 0, "[pipeline] settings have their own options: --seed", {"pipeline.seed=3"});
}

// Parameters each in range but inconsistent together are refused by the
// stage's constructor; the plan creates every stage so that shows up at
// --validate, at the stage's table, not in the run after earlier stages.
TEST(Plan, AStageThatRefusesItsParametersFailsThePlan) {
  const std::string interval = "[stages.iv]\nplugin = \"test.interval\"\n";  // lines 1-2
  expect_one_error(interval + "lo = 0.9\nhi = 0.1\n", 1, "parameters refused by test.interval: lo must be < hi");
  const auto errors = errors_of(interval, {"iv.lo=0.9", "iv.hi=0.1"});
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].stage, "iv");
  EXPECT_NE(errors[0].message.find("(with --set iv.lo=0.9 --set iv.hi=0.1)"), std::string::npos) << errors[0].str();
  Diagnostics d;
  plan_of(interval + "lo = 0.1\nhi = 0.9\n", d);
  EXPECT_TRUE(d.ok()) << d.errors[0].str();
  // A value already refused by its range is not reported a second time.
  expect_one_error(interval + "lo = 5\n", 3, "must be in");
}

// The plugin and inputs are the pipeline's structure, not parameters.
TEST(Overrides, PluginAndInputsCannotBeSet) {
  expect_one_error(source, 1, "--set src.plugin=test.join: a stage's plugin cannot be changed with --set",
                   {"src.plugin=test.join"});
  expect_one_error(source, 1, "pipelines/ablations/", {"src.plugin=test.join"});
  expect_one_error(source, 1, "a stage's inputs cannot be changed with --set", {"src.inputs=x"});
}

TEST(Plan, ResolvedTomlRoundTrips) {
  Diagnostics d;
  const Plan plan = plan_of("[pipeline]\nseed = 4\n" + chain, d);
  ASSERT_TRUE(d.ok());
  Diagnostics d2;
  const Plan again = plan_of(plan.resolved_toml(), d2);
  ASSERT_TRUE(d2.ok()) << d2.errors[0].str();
  EXPECT_EQ(again.resolved_toml(), plan.resolved_toml());
  EXPECT_NE(plan.describe().find("level 2"), std::string::npos);
}

// Problems come out as a reader meets them in the file, whichever check
// found them first; file-wide ones lead, and other files keep their order.
TEST(Diagnostics, SortByLocationOrdersByFileThenLineThenColumn) {
  Diagnostics d;
  d.error({"p.toml", 13, 11}, "describe", "samples out of range");
  d.error({"p.toml", 8, 1}, "load", "unknown parameter");
  d.error({"other.toml", 2, 1}, "", "elsewhere");
  d.error({"p.toml", 12, 22}, "describe", "no such output");
  d.error({"p.toml", 0, 0}, "", "--set names no stage");
  d.error({"p.toml", 12, 22}, "describe", "second at the same place");
  d.warning({"p.toml", 10, 1}, "describe", "unused output");
  d.warning({"p.toml", 6, 1}, "load", "unused output");
  d.sort_by_location();
  std::vector<std::string> order;
  for (const auto& e : d.errors) order.push_back(e.message);
  EXPECT_EQ(order, (std::vector<std::string>{"--set names no stage", "unknown parameter", "no such output",
                                             "second at the same place", "samples out of range", "elsewhere"}));
  ASSERT_EQ(d.warnings.size(), 2u);
  EXPECT_EQ(d.warnings[0].where.line, 6);
  EXPECT_EQ(d.first_error().message(), "--set names no stage");
}

// A pipeline file that is not there: the nearest .toml beside it is named.
TEST(PipelineFile, AMissingFileSuggestsTheNearestPipeline) {
  lista_test::TempDir dir;
  dir.write("volumetric-octomap.toml", "");
  dir.write("lista.toml", "");
  for (const auto& [asked, suggested] : std::vector<std::pair<std::string, std::string>>{
           {"octomap.toml", "volumetric-octomap.toml"}, {"lista.tml", "lista.toml"}}) {
    Diagnostics d;
    try {
      parse_pipeline_file((dir.path / asked).string(), d);
      ADD_FAILURE() << asked << " opened";
    } catch (const lista::Error& e) {
      EXPECT_NE(std::string(e.what()).find("(did you mean '" + (dir.path / suggested).string() + "'?)"),
                std::string::npos)
          << e.what();
    }
  }
}

// The TOML mistakes people make most read plainly, at their line.
TEST(PipelineFile, CommonTomlMistakesAreSaidPlainly) {
  for (const auto& [text, where, message] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"[stages.a]\nplugin = \"test.source\"\n[stages.a]\nplugin = \"test.source\"\n", "p.toml:3:",
            "stage 'a' is defined twice; stage ids are unique, rename one"},
           {"[pipeline]\nname = \"x\"\nname = \"y\"\n", "p.toml:3:", "key 'name' is given twice in its table"},
           {"[pipeline]\nname = \"x\n", "p.toml:2:", "a string is not closed"},
           {"[pipeline]\nname = x y\n", "p.toml:2:", "not a TOML value (text needs quotes"}}) {
    Diagnostics d;
    try {
      parse_pipeline_text(text, "p.toml", d);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const lista::Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind(where, 0), 0u) << m;
      EXPECT_NE(m.find("TOML syntax error: " + message), std::string::npos) << m;
    }
  }
}

TEST(PipelineFile, ADotInAStageIdIsNamed) {
  expect_one_error("[stages.a.b]\nplugin = \"test.source\"\n", 1, "[stages.a.b]: a stage id cannot hold a dot; write [stages.a_b]");
}

// A parameter group: a TOML sub-table of the stage ([stages.src.noise] or an
// inline table) holds the parameters noise.<key>; --set src.noise.sigma=...
// reaches the same parameter; an unknown key is named with its group.
TEST(Pipeline, ParameterGroupsAreSubTablesOfTheStage) {
  Diagnostics d;
  const Plan table = plan_of(source + "[stages.src.noise]\nenabled = true\nsigma = 0.25\n", d);
  ASSERT_TRUE(d.ok()) << d.errors.front().str();
  EXPECT_TRUE(table.stages.at(0).params.get<bool>("noise.enabled"));
  EXPECT_DOUBLE_EQ(table.stages.at(0).params.get<double>("noise.sigma"), 0.25);
  Diagnostics d2;
  const Plan inline_table = plan_of(source + "noise = { sigma = 0.5 }\n", d2);
  ASSERT_TRUE(d2.ok()) << d2.errors.front().str();
  EXPECT_DOUBLE_EQ(inline_table.stages.at(0).params.get<double>("noise.sigma"), 0.5);
  EXPECT_FALSE(inline_table.stages.at(0).params.get<bool>("noise.enabled"));
  Diagnostics d3;
  const Plan set = plan_of(source, d3, {"src.noise.sigma=0.75"});
  ASSERT_TRUE(d3.ok()) << d3.errors.front().str();
  EXPECT_DOUBLE_EQ(set.stages.at(0).params.get<double>("noise.sigma"), 0.75);
  expect_one_error(source + "[stages.src.noise]\nsigam = 1.0\n", 4, "noise.sigam");
  expect_one_error(source + "[stages.src.noise]\nsigma = -1.0\n", 4, ">= 0");
  expect_one_error(source + "[stages.src.noise.deeper]\nx = 1\n", 3, "unknown parameter 'noise.deeper'");
}

// A renamed parameter (test.source: `sigma` is now `noise.sigma`; its
// `noise_level` 0 meant off): the old name in the file or in --set fills the
// new parameter, and one warning at the key names the new spelling.
TEST(Pipeline, OldParameterNamesFillTheNewOnesWithAWarning) {
  // The warnings that name a new spelling (a lone source also has an unused output).
  const auto renames = [](const Diagnostics& d) {
    std::vector<Diagnostic> out;
    for (const auto& w : d.warnings)
      if (w.message.find(" is now ") != std::string::npos) out.push_back(w);
    return out;
  };
  Diagnostics d;
  const Plan plan = plan_of(source + "sigma = 0.25\n", d);
  ASSERT_TRUE(d.ok()) << d.errors.front().str();
  EXPECT_DOUBLE_EQ(plan.stages.at(0).params.get<double>("noise.sigma"), 0.25);
  EXPECT_TRUE(plan.stages.at(0).params.is_set("noise.sigma"));
  ASSERT_EQ(renames(d).size(), 1u);
  EXPECT_EQ(renames(d)[0].str(),
            "p.toml:3:1: stage 'src': parameter 'sigma' is now 'noise.sigma' (the old name works until the next release)");
  EXPECT_EQ(plan.resolved_toml().find("\nsigma ="), std::string::npos) << "the plan speaks the new names only";

  Diagnostics d2;
  const Plan set = plan_of(source, d2, {"src.sigma=0.5"});
  ASSERT_TRUE(d2.ok()) << d2.errors.front().str();
  EXPECT_DOUBLE_EQ(set.stages.at(0).params.get<double>("noise.sigma"), 0.5);
  ASSERT_EQ(renames(d2).size(), 1u);
  EXPECT_EQ(renames(d2)[0].message,
            "--set src.sigma=0.5: parameter 'sigma' is now 'noise.sigma' (the old name works until the next release)");

  // An old sentinel reads as the new switch, and the warning says how.
  Diagnostics d3;
  const Plan off = plan_of(source + "noise_level = 0.0\n", d3);
  ASSERT_TRUE(d3.ok()) << d3.errors.front().str();
  EXPECT_FALSE(off.stages.at(0).params.get<bool>("noise.enabled"));
  EXPECT_TRUE(off.stages.at(0).params.is_set("noise.enabled"));
  ASSERT_EQ(renames(d3).size(), 1u);
  EXPECT_EQ(renames(d3)[0].message, "parameter 'noise_level' is now 'noise.sigma' (the old name works until the next "
                                    "release); 0.0 reads as noise.enabled = false");
  Diagnostics d4;
  const Plan on = plan_of(source + "noise_level = 0.3\n", d4);
  ASSERT_TRUE(d4.ok()) << d4.errors.front().str();
  EXPECT_TRUE(on.stages.at(0).params.get<bool>("noise.enabled"));
  EXPECT_DOUBLE_EQ(on.stages.at(0).params.get<double>("noise.sigma"), 0.3);

  // Checked as the new parameter; written under both names, an error.
  expect_one_error(source + "sigma = -1.0\n", 3, "parameter 'noise.sigma' must be >= 0");
  expect_one_error(source + "noise_level = \"loud\"\n", 3, "parameter 'noise_level' must be float");
  expect_one_error(source + "sigma = 0.1\n[stages.src.noise]\nsigma = 0.2\n", 5,
                   "parameter 'noise.sigma' is written twice, as 'sigma' and as 'noise.sigma'; keep 'noise.sigma'");
  // An old name is no parameter: a typo of it suggests the new one, and the known names are the new ones.
  const auto unknown = errors_of(source + "sigmaa = 1.0\n");
  ASSERT_EQ(unknown.size(), 1u);
  EXPECT_NE(unknown[0].message.find("(did you mean 'noise.sigma'?)"), std::string::npos) << unknown[0].str();
  expect_one_error(source + "noise_levl = 1.0\n", 3, "(did you mean 'noise.sigma'?)");
  const std::string known = "known: count, missions, scale, mode, verbose, weights, tags, noise.enabled, noise.sigma";
  EXPECT_EQ(unknown[0].message.substr(unknown[0].message.size() - known.size()), known) << unknown[0].str();
}
