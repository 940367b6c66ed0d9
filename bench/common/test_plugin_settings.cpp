#include <lista_bench/plugin_settings.hpp>

#include <gtest/gtest.h>

using namespace lista;
using namespace lista::bench;

namespace {

StageInfo aligner() {
  StageInfo s;
  s.name = "align.test";
  s.params = {ParamSpec::integer("scan_edges", 2, "").range(0, 10), ParamSpec::real("voxel", 0.2, "").range(0.01, 5.0),
              ParamSpec::boolean("verify", true, ""), ParamSpec::text("loss", "cauchy", "").one_of({"cauchy", "none"})};
  return s;
}

// The error one setting gives, or "" when it is accepted.
std::string refusal(const std::string& text) {
  try {
    params_of("align.test", aligner(), {parse_setting(text, "align.test.voxel=0.1")});
  } catch (const Error& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST(BenchSettings, ValuesAreTypedAsInAPipeline) {
  const StageInfo info = aligner();
  const Params p = params_of("align.test", info,
                             {parse_setting("align.test.scan_edges=0", ""), parse_setting("align.test.voxel=1", ""),
                              parse_setting("align.test.verify=false", ""), parse_setting("align.test.loss=none", ""),
                              parse_setting("other.voxel=3", "")});
  EXPECT_EQ(p.get<int>("scan_edges"), 0);
  EXPECT_DOUBLE_EQ(p.get<double>("voxel"), 1.0);  // an integer for a real parameter
  EXPECT_FALSE(p.get<bool>("verify"));
  EXPECT_EQ(p.get<std::string>("loss"), "none");
  EXPECT_EQ(params_of("align.test", info, {}).get<int>("scan_edges"), 2);
}

// What lista-bench alignment once did with these: cut 1.9 to 1, 'error:
// stoll', false for anything but "true", and kept the default for a typo.
TEST(BenchSettings, WrongTypesRangesAndNamesAreOneLineErrors) {
  EXPECT_EQ(refusal("align.test.scan_edges=1.9"), "--set align.test.scan_edges=1.9: 'scan_edges' must be int, got float 1.9");
  EXPECT_EQ(refusal("align.test.scan_edges=abc"),
            "--set align.test.scan_edges=abc: 'scan_edges' must be int, got string \"abc\"");
  EXPECT_EQ(refusal("align.test.verify=yes"), "--set align.test.verify=yes: 'verify' must be bool, got string \"yes\"");
  EXPECT_EQ(refusal("align.test.scan_edges=11"), "--set align.test.scan_edges=11: 'scan_edges' must be in [0, 10], got 11");
  EXPECT_EQ(refusal("align.test.loss=huber"),
            "--set align.test.loss=huber: 'loss' must be one of \"cauchy\", \"none\", got \"huber\"");
  EXPECT_EQ(refusal("align.test.scan_edge=1"), "--set align.test.scan_edge=1: align.test has no parameter 'scan_edge'");
  for (const char* malformed : {"align.test.voxel", "voxel=1", ".voxel=1", "align.test.=1"})
    EXPECT_EQ(refusal(malformed), "--set '" + std::string(malformed) +
                                      "' is not of the form <plugin>.<param>=<value> (e.g. align.test.voxel=0.1)");
}

TEST(BenchSettings, ASettingForAPluginNotComparedIsAnError) {
  const std::vector<Setting> settings = {parse_setting("align.test.voxel=1", ""), parse_setting("align.scan_edges=0", "")};
  EXPECT_NO_THROW(check_compared({settings[0]}, {"align.test", "align.icp"}));
  try {
    check_compared(settings, {"align.test", "align.icp"});
    FAIL() << "align.scan_edges=0 names no compared plugin";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "--set align.scan_edges=0: 'align' is not among the plugins compared (align.test, align.icp)");
  }
}
