// lista-bench alignment's --set as a user gives it: keyed by plugin name,
// parsed and checked like lista-run's --set. A wrong type, a value out of
// range, an undeclared parameter or a plugin the run does not compare is one
// line of error and a non-zero exit before any dataset is read; a good
// setting reaches the plugin it names.
#include "e2e_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

std::string bench(const std::string& args) {
  return e2e::bin("lista-bench-alignment") + " " + args + " 2>&1";
}

}  // namespace

TEST(BenchAlignment, EveryBadSettingIsOneLineOfError) {
  const std::string nowhere = "/nonexistent/dataset";
  struct Case {
    const char* set;
    const char* says;
  };
  for (const Case& c : {
           Case{"align.posegraph.scans.neighbours=1.9", "'scans.neighbours' must be int, got float 1.9"},
           Case{"align.posegraph.scans.neighbours=abc", "'scans.neighbours' must be int, got string \"abc\""},
           Case{"align.posegraph.scans.neighbours=11", "'scans.neighbours' must be in [0, 10], got 11"},
           Case{"align.posegraph.scan_edge=1", "align.posegraph has no parameter 'scan_edge'"},
           Case{"align.scan_edges=0", "'align' is not among the plugins compared (align.posegraph, align.icp)"},
           Case{"align.posegraph.voxel", "is not of the form <plugin>.<param>=<value>"},
       }) {
    const auto r = e2e::run(bench(nowhere + " --set " + c.set));
    EXPECT_NE(r.status, 0) << c.set;
    EXPECT_EQ(r.output.find("lista-bench-alignment: error: --set"), 0u) << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
  }
  // A plugin left out of --stages is not compared either.
  const auto left_out = e2e::run(bench(nowhere + " --stages align.posegraph --set align.icp.voxel=0.3"));
  EXPECT_NE(left_out.status, 0);
  EXPECT_NE(left_out.output.find("'align.icp' is not among the plugins compared (align.posegraph)"), std::string::npos)
      << left_out.output;
  // A good setting passes the checks: what stops this run is the dataset.
  const auto good = e2e::run(bench(nowhere + " --stages align.icp --set align.icp.iterations=5 --set align.icp.voxel=1"));
  EXPECT_NE(good.status, 0);
  EXPECT_EQ(good.output.find("--set"), std::string::npos) << good.output;
  EXPECT_NE(good.output.find(nowhere + ": no such dataset folder"), std::string::npos) << good.output;
  EXPECT_EQ(good.output.find("| dataset |"), std::string::npos) << "no table header before the error";
  // Stages are found as lista-run finds them: a misspelt one is named with
  // the nearest, and a stage of another kind is refused.
  const auto misspelt = e2e::run(bench(nowhere + " --stages align.posgraph"));
  EXPECT_NE(misspelt.status, 0);
  EXPECT_NE(misspelt.output.find("unknown plugin 'align.posgraph' (did you mean 'align.posegraph'?)"),
            std::string::npos)
      << misspelt.output;
  const auto other_kind = e2e::run(bench(nowhere + " --stages describe.esf"));
  EXPECT_NE(other_kind.status, 0);
  EXPECT_NE(other_kind.output.find("describe.esf is not an align stage"), std::string::npos) << other_kind.output;
}

// align.icp refuses a registration with less overlap than min_overlap: set
// near 1, its first run (from the centroid guess, overlap about 0.6 on
// `tiny`) says so in its row, and only that plugin's runs see the setting.
TEST(BenchAlignment, AGoodSettingReachesThePluginItNames) {
  e2e::TempDir dir("bench_alignment");
  const std::string data = (dir.path() / "tiny").string();
  const auto sim = e2e::simulate("--preset tiny --seed 1", data);
  ASSERT_EQ(sim.status, 0) << sim.output;
  auto icp_row = [&](const std::string& set) {
    // The table alone on stdout: log lines between its rows would split it.
    const std::string log = (dir.path() / "log.txt").string();
    const auto r = e2e::run(e2e::bin("lista-bench-alignment") + " " + data + " --stages align.icp --threads 2 " + set +
                            " 2>" + log);
    EXPECT_EQ(r.status, 0) << r.output << e2e::read_file(log);
    for (const auto& row : e2e::markdown_rows(r.output))
      if (row.size() > 3 && row[1] == "align.icp") return row[3];  // ATE after, or the stage's error
    ADD_FAILURE() << "no align.icp row in: " << r.output;
    return std::string();
  };
  EXPECT_EQ(icp_row("").find("error"), std::string::npos);
  EXPECT_NE(icp_row("--set align.icp.min_overlap=0.99").find("< min_overlap 0.99"), std::string::npos);
}
