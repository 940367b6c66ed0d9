#include <lista_cli/folders.hpp>
#include <lista_cli/parse.hpp>

#include <gtest/gtest.h>

#include <optional>

#include <algorithm>
#include <sstream>
#include <vector>

namespace {

struct Parsed {
  std::optional<int> code;
  std::string err, help;
};

Parsed parse(std::vector<const char*> args, int& count, bool& flag) {
  CLI::App app{"a test program"};
  app.add_option("--count", count, "how many")->check(CLI::PositiveNumber);
  app.add_flag("--flag", flag, "a switch");
  args.insert(args.begin(), "/some/build/path/prog");
  std::ostringstream err;
  auto* old = std::cerr.rdbuf(err.rdbuf());
  Parsed p;
  p.code = lista::cli::parse_command_line(app, int(args.size()), args.data(), "lista-prog");
  std::cerr.rdbuf(old);
  p.err = err.str();
  p.help = app.help();
  return p;
}

}  // namespace

TEST(CliParse, GoodArgumentsGoOn) {
  int count = 3;
  bool flag = false;
  const Parsed p = parse({"--count", "5", "--flag"}, count, flag);
  EXPECT_FALSE(p.code.has_value());
  EXPECT_EQ(count, 5);
  EXPECT_TRUE(flag);
}

TEST(CliParse, HelpShowsTheProgramNameAndDefaults) {
  int count = 3;
  bool flag = false;
  const Parsed p = parse({}, count, flag);
  EXPECT_NE(p.help.find("Usage: lista-prog"), std::string::npos) << p.help;
  EXPECT_NE(p.help.find("=3"), std::string::npos) << p.help;
  EXPECT_EQ(p.help.find("{false}"), std::string::npos) << p.help;  // no default printed for a flag
  EXPECT_EQ(p.help.find("=0"), std::string::npos) << p.help;
}

TEST(CliParse, AUsageErrorIsOneLineAndExitStatus2) {
  int count = 3;
  bool flag = false;
  const Parsed bad = parse({"--count", "-1"}, count, flag);
  ASSERT_TRUE(bad.code.has_value());
  EXPECT_EQ(*bad.code, 2);
  EXPECT_EQ(bad.err.rfind("lista-prog: error: --count: ", 0), 0u) << bad.err;
  EXPECT_NE(bad.err.find("(see --help)\n"), std::string::npos) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1);
  const Parsed unknown = parse({"--nope"}, count, flag);
  EXPECT_EQ(unknown.code.value_or(0), 2);
}

// A range check passes NaN (every comparison with it is false): every
// floating-point option refuses NaN and infinity itself.
TEST(CliParse, FloatOptionsRefuseNanAndInfinity) {
  for (const char* bad : {"nan", "NaN", "inf", "-inf"}) {
    CLI::App app{"a test program"};
    double margin = 0.5;
    app.add_option("--margin", margin, "a margin")->check(CLI::Range(0.0, 2.0));
    const char* args[] = {"prog", "--margin", bad};
    std::ostringstream err;
    auto* old = std::cerr.rdbuf(err.rdbuf());
    const auto code = lista::cli::parse_command_line(app, 3, args, "lista-prog");
    std::cerr.rdbuf(old);
    EXPECT_EQ(code.value_or(0), 2) << bad;
    if (std::string(bad).find("inf") == std::string::npos) {  // infinity: the range check says it first
      EXPECT_NE(err.str().find("must be a finite number, got "), std::string::npos) << err.str();
    }
  }
}

namespace {
// Parses `--value <value>` checked by `validator`; returns the stderr text,
// or nullopt when the value was accepted.
std::optional<std::string> check_value(const CLI::Validator& validator, const char* value) {
  CLI::App app{"a test program"};
  double v = 0.0;
  app.add_option("--value", v, "a value")->check(validator);
  const char* args[] = {"prog", "--value", value};
  std::ostringstream err;
  auto* old = std::cerr.rdbuf(err.rdbuf());
  const auto code = lista::cli::parse_command_line(app, 3, args, "lista-prog");
  std::cerr.rdbuf(old);
  if (!code) return std::nullopt;
  return err.str();
}
}  // namespace

// at_least: the bound said plainly, the bound itself accepted.
TEST(CliParse, AtLeastSaysItsBoundPlainly) {
  for (const char* ok : {"0", "2.5"}) EXPECT_FALSE(check_value(lista::cli::at_least(0.0), ok)) << ok;
  const auto err = check_value(lista::cli::at_least(0.0), "-1");
  ASSERT_TRUE(err);
  EXPECT_NE(err->find("--value: must be at least 0, got -1 (see --help)"), std::string::npos) << *err;
}

// between: both bounds said plainly and accepted, outside refused.
TEST(CliParse, BetweenSaysItsBoundsPlainly) {
  for (const char* ok : {"0.005", "1"}) EXPECT_FALSE(check_value(lista::cli::between(0.005, 1.0), ok)) << ok;
  for (const std::string bad : {"0", "1.5"}) {
    const auto err = check_value(lista::cli::between(0.005, 1.0), bad.c_str());
    ASSERT_TRUE(err) << bad;
    EXPECT_NE(err->find("--value: must be between 0.005 and 1, got " + bad), std::string::npos) << *err;
  }
  // Numbers a double cannot hold would become inf or 0 and skip the check.
  for (const std::string huge : {"1e400", "1e-400"})
    for (const CLI::Validator& v : {lista::cli::between(0.005, 1.0), lista::cli::at_least(0.0)}) {
      const auto err = check_value(v, huge.c_str());
      ASSERT_TRUE(err) << huge;
      EXPECT_NE(err->find("is out of range for a number, got " + huge), std::string::npos) << *err;
    }
}

// An output at or under the dataset is refused; a sibling sharing a name
// prefix (data vs data2) or any other folder is fine.
TEST(CliFolders, OutputInsideTheDatasetIsRefused) {
  using lista::cli::output_inside_dataset;
  const std::string d = "/tmp/lista-cli-test/data";
  for (const std::string& out : {d, d + "/", d + "/A/out", d + "/../data/run"})
    EXPECT_EQ(output_inside_dataset(d, out, "--out").find("--out " + out + " lies inside the dataset " + d), 0u) << out;
  for (const std::string& out : {std::string("/tmp/lista-cli-test/data2"), std::string("/tmp/lista-cli-test"),
                                std::string("/tmp/other/run"), std::string()})
    EXPECT_EQ(output_inside_dataset(d, out, "--out"), "") << out;
}
