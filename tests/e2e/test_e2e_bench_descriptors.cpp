// lista-bench-descriptors as a user runs it: on a small `lista-sim views`
// folder it describes every held-out view, writes the table and a JSON file
// whose numbers are scores (with top-1 split by view size, sensor, distance
// and coverage), and it refuses a folder that is not there.
#include "e2e_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

using nlohmann::json;

namespace {
// A small `lista-sim views` set in `views`; false (the failure recorded)
// when lista-sim failed.
bool simulate_views(const std::string& views, const std::string& args) {
  const auto sim = e2e::run(e2e::bin("lista-sim") + " views " + args + " --out " + views + " 2>&1");
  EXPECT_EQ(sim.status, 0) << sim.output;
  return sim.status == 0;
}
}  // namespace

TEST(BenchDescriptors, ScoresTheHeldOutViewsOfASimulatedSet) {
  e2e::TempDir dir("bench_descriptors");
  const std::string views = (dir.path() / "views").string(), out = (dir.path() / "esf.json").string();
  ASSERT_TRUE(simulate_views(views, "--objects 120 --views-per-object 3 --seed 2"));
  const auto bench = e2e::run(e2e::bin("lista-bench-descriptors") + " --views " + views +
                              " --plugins describe.esf,describe.shot --set describe.shot.voxel=0.05 --json " + out + " 2>&1");
  ASSERT_EQ(bench.status, 0) << bench.output;
  EXPECT_NE(bench.output.find("| describe.esf | 640 |"), std::string::npos) << bench.output;

  size_t held_out = 0;
  const json index = json::parse(e2e::read_file(views + "/index.json"));
  for (const auto& v : index.at("views"))
    held_out += v.at("split").get<std::string>() != "train" && v.at("points").get<int>() > 0;
  const json rows = json::parse(e2e::read_file(out));
  ASSERT_EQ(rows.size(), 2u);
  const json& r = rows[0];
  EXPECT_EQ(r.at("plugin"), "describe.esf");
  // Which build ran: a user's plugin of the same name may shadow the shipped one.
  EXPECT_NE(r.at("library").get<std::string>().find("liblista_describe_esf.so"), std::string::npos) << r.dump();
  EXPECT_FALSE(r.at("version").get<std::string>().empty());
  EXPECT_EQ(r.at("objects").get<size_t>(), held_out);
  EXPECT_GE(r.at("variants").get<int>(), r.at("shapes").get<int>());
  for (const char* key : {"top1", "map", "purity", "top1_variants"}) {
    EXPECT_GT(r.at(key).get<double>(), 0.0) << key;  // ESF tells some shapes apart
    EXPECT_LE(r.at(key).get<double>(), 1.0) << key;
  }
  EXPECT_GT(r.at("median_ms").get<double>(), 0.0);
  EXPECT_GE(r.at("p95_ms").get<double>(), r.at("median_ms").get<double>());
  EXPECT_FALSE(std::filesystem::exists(out + ".tmp"));
  // Every simulated view says its size, sensor, distance and shape: each
  // breakdown puts every view in one bin, and its hits add up to top-1.
  for (const char* key : {"top1_by_view_size", "top1_by_sensor", "top1_by_distance", "top1_by_coverage"}) {
    ASSERT_TRUE(r.contains(key)) << key;
    size_t views_in_bins = 0;
    double hits = 0.0;
    for (const json& bin : r.at(key)) {
      views_in_bins += bin.at("views").get<size_t>();
      if (bin.at("views").get<size_t>() == 0) {
        EXPECT_TRUE(bin.at("top1").is_null()) << key << ": an empty bin has no top-1";
        continue;
      }
      hits += bin.at("top1").get<double>() * bin.at("views").get<double>();
    }
    EXPECT_EQ(views_in_bins, held_out) << key;
    EXPECT_NEAR(hits / double(held_out), r.at("top1").get<double>(), 1e-9) << key;
  }
  EXPECT_NE(bench.output.find("top-1 by what the view shows:"), std::string::npos) << bench.output;
  EXPECT_FALSE(r.contains("set")) << "the setting names describe.shot only";
  ASSERT_TRUE(rows[1].contains("set")) << rows[1].dump();
  EXPECT_EQ(rows[1].at("set"), json::array({"describe.shot.voxel=0.05"}));

  // A parameter the plugin does not declare, a value out of range or of the
  // wrong type, a plugin not compared, a malformed setting: an error before
  // any plugin runs, and no JSON.
  for (const char* bad : {"describe.esf.nope=1", "describe.shot.voxel=5", "describe.shot.voxel=dense",
                                 "describe.learned.samples=2", "esf=3"}) {
    const std::string json_bad = (dir.path() / "bad.json").string();
    const auto r = e2e::run(e2e::bin("lista-bench-descriptors") + " --views " + views +
                            " --plugins describe.esf,describe.shot --json " + json_bad + " --set " + bad + " 2>&1");
    EXPECT_NE(r.status, 0) << bad;
    EXPECT_NE(r.output.find("--set"), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(json_bad)) << bad;
  }
}

// One plugin twice, under two names (a user's own weights beside the
// shipped ones): each entry gets the settings that name it, its own row in
// the table, the JSON and --rows, and the name appears everywhere the
// plugin's would. Two entries of one name are refused before any run.
TEST(BenchDescriptors, APluginComparedWithItselfUnderAnotherName) {
  e2e::TempDir dir("bench_descriptors_named");
  const std::string views = (dir.path() / "views").string(), out = (dir.path() / "named.json").string(),
                    rows_dir = (dir.path() / "rows").string();
  ASSERT_TRUE(simulate_views(views, "--objects 30 --views-per-object 3 --seed 3"));
  const std::string bench = e2e::bin("lista-bench-descriptors") + " --views " + views + " --all-splits --max-views 12";
  const auto r = e2e::run(bench + " --plugins describe.shot,coarse=describe.shot --set coarse.voxel=0.08 --json " +
                          out + " --rows " + rows_dir + " 2>&1");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("| describe.shot | 352 |"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("| coarse (describe.shot) | 352 |"), std::string::npos) << r.output;
  const json rows = json::parse(e2e::read_file(out));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("name"), "describe.shot");
  EXPECT_EQ(rows[1].at("name"), "coarse");
  EXPECT_EQ(rows[1].at("plugin"), "describe.shot");
  EXPECT_FALSE(rows[0].contains("set"));
  EXPECT_EQ(rows[1].at("set"), json::array({"coarse.voxel=0.08"}));
  EXPECT_TRUE(rows[1].contains("top1_by_sensor")) << "breakdowns go to the entry by its name";
  const std::string fine = e2e::read_file(rows_dir + "/describe.shot.csv"), coarse = e2e::read_file(rows_dir + "/coarse.csv");
  EXPECT_FALSE(fine.empty());
  EXPECT_FALSE(coarse.empty());
  EXPECT_NE(fine, coarse) << "the voxel setting reached the second entry only";

  for (const char* bad : {"describe.esf,describe.esf", "two words=describe.esf", "=describe.esf", "a="}) {
    const auto refused = e2e::run(bench + " --plugins '" + std::string(bad) + "' 2>&1");
    EXPECT_NE(refused.status, 0) << bad;
    EXPECT_NE(refused.output.find("--plugins"), std::string::npos) << refused.output;
    EXPECT_EQ(refused.output.find("| describe.esf |"), std::string::npos) << refused.output;
  }
}

// The bench checks a plugin's outputs as lista-run does: an undeclared
// output or a broken descriptor contract is one line naming the plugin.
TEST(BenchDescriptors, ChecksOutputsAsListaRunDoes) {
#ifndef TEST_PLUGIN_GOOD_DIR
  GTEST_SKIP() << "core test plugins not built";
#else
  e2e::TempDir dir("bench-desc-check");
  const std::string views = (dir.path() / "views").string();
  ASSERT_TRUE(simulate_views(views, "--objects 12 --views-per-object 2 --seed 4 --threads 2"));
  for (const auto& [mode, says] : std::vector<std::pair<std::string, std::string>>{
           {"extra_output", "produced output 'extra' that test.describe does not declare"},
           {"no_columns", "descriptors have no columns (0-d)"},
           {"not_finite", "holds a NaN or infinite value"}}) {
    const auto r = e2e::run(e2e::bin("lista-bench-descriptors") + " --views " + views + " --plugin-dir " +
                            TEST_PLUGIN_GOOD_DIR + " --plugins test.describe --set test.describe.mode=" + mode +
                            " --all-splits 2>&1");
    EXPECT_NE(r.status, 0) << mode;
    EXPECT_NE(r.output.find(says), std::string::npos) << mode << ": " << r.output;
    EXPECT_NE(r.output.find("test.describe"), std::string::npos) << r.output;
  }
#endif
}

TEST(BenchDescriptors, AMissingViewsFolderIsAnErrorNamingIt) {
  const auto r = e2e::run(e2e::bin("lista-bench-descriptors") + " --views /nonexistent/views 2>&1");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("/nonexistent/views/index.json: not found"), std::string::npos) << r.output;
}

// A folder whose views are all for training (one's own scans, split left
// out) has nothing held out: a one-line error that names the way out, not
// an empty table; --all-splits scores them. Bad outputs fail up front.
TEST(BenchDescriptors, AFolderWithNothingHeldOutIsAnErrorUnlessAllSplitsAreScored) {
  e2e::TempDir dir("bench_no_held_out");
  const std::string views = (dir.path() / "views").string();
  ASSERT_TRUE(simulate_views(views, "--objects 12 --views-per-object 2 --seed 4"));
  std::string index = e2e::read_file(views + "/index.json");
  for (const std::string held : {"\"split\": \"val\"", "\"split\": \"test\""})
    for (size_t at = index.find(held); at != std::string::npos; at = index.find(held))
      index.replace(at, held.size(), "\"split\": \"train\"");
  std::ofstream(views + "/index.json") << index;
  const std::string bench = e2e::bin("lista-bench-descriptors") + " --views " + views + " --plugins describe.esf";
  const auto refused = e2e::run(bench + " 2>&1");
  EXPECT_NE(refused.status, 0);
  EXPECT_NE(refused.output.find("no held-out views (index.json split 'val' or 'test'); score every view with --all-splits"),
            std::string::npos)
      << refused.output;
  const auto all = e2e::run(bench + " --all-splits 2>&1");
  EXPECT_EQ(all.status, 0) << all.output;
  EXPECT_NE(all.output.find("| describe.esf | 640 |"), std::string::npos) << all.output;
  // An output that cannot be written fails before any plugin runs.
  const auto bad_json = e2e::run(bench + " --all-splits --json /nonexistent/out.json 2>&1");
  EXPECT_NE(bad_json.status, 0);
  EXPECT_NE(bad_json.output.find("cannot write /nonexistent/out.json.tmp: choose another --json"), std::string::npos)
      << bad_json.output;
  EXPECT_EQ(bad_json.output.find("| describe.esf |"), std::string::npos) << bad_json.output;
  const auto one = e2e::run(bench + " --all-splits --max-views 1 2>&1");
  EXPECT_NE(one.status, 0);
  EXPECT_NE(one.output.find("give at least two"), std::string::npos) << one.output;
}

// Views are lifted to a random height and their floor goes with them as the
// objects' floor_z: a floor model reads it, so withholding it (--no-floor)
// changes describe.learned's rows but not ESF's (which ignores the floor),
// as does an error added to the floor (--floor-error); the JSON records
// which way the set was scored.
TEST(BenchDescriptors, TheFloorIsGivenUnlessWithheld) {
#ifndef LISTA_HAVE_LEARNED
  GTEST_SKIP() << "describe.learned not built (no libtorch)";
#endif
  e2e::TempDir dir("bench_floor");
  const std::string views = (dir.path() / "views").string();
  ASSERT_TRUE(simulate_views(views, "--objects 40 --views-per-object 2 --seed 3"));
  auto bench = [&](const std::string& name, const std::string& extra) {
    const std::string base = (dir.path() / name).string();
    const auto r = e2e::run(e2e::bin("lista-bench-descriptors") + " --views " + views +
                            " --plugins describe.learned,describe.esf --json " + base + ".json --rows " + base +
                            " " + extra + " 2>&1");
    EXPECT_EQ(r.status, 0) << r.output;
    return std::make_pair(r.output, json::parse(e2e::read_file(base + ".json")));
  };
  const auto [given_text, given] = bench("given", "");
  const auto [withheld_text, withheld] = bench("withheld", "--no-floor");
  const auto [off_text, off] = bench("off", "--floor-error 0.05");
  EXPECT_NE(given_text.find("floor given"), std::string::npos) << given_text;
  EXPECT_NE(withheld_text.find("floor withheld"), std::string::npos) << withheld_text;
  EXPECT_NE(off_text.find("floor given, off by 50 mm"), std::string::npos) << off_text;
  EXPECT_DOUBLE_EQ(off[0].at("floor_error_m").get<double>(), 0.05);
  EXPECT_DOUBLE_EQ(given[0].at("floor_error_m").get<double>(), 0.0);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_TRUE(given[i].at("floor_given").get<bool>());
    EXPECT_FALSE(withheld[i].at("floor_given").get<bool>());
  }
  const auto rows = [&](const std::string& name, const std::string& plugin) {
    return e2e::read_file((dir.path() / name / (plugin + ".csv")).string());
  };
  EXPECT_NE(rows("given", "describe.learned"), rows("withheld", "describe.learned"));
  ASSERT_FALSE(rows("given", "describe.esf").empty());
  EXPECT_EQ(rows("given", "describe.esf"), rows("withheld", "describe.esf"));
  EXPECT_NE(rows("given", "describe.learned"), rows("off", "describe.learned"));
  EXPECT_EQ(rows("given", "describe.esf"), rows("off", "describe.esf"));  // the error draws move nothing else
  // An error without a floor is a contradiction, refused before any work.
  const auto both = e2e::run(e2e::bin("lista-bench-descriptors") + " --views " + views +
                             " --plugins describe.esf --no-floor --floor-error 0.05 2>&1");
  EXPECT_NE(both.status, 0);
  EXPECT_NE(both.output.find("excludes"), std::string::npos) << both.output;
}

// bench/descriptors/confusions.py reads the rows the benchmark wrote and
// redoes the nearest-neighbour search in plain Python: its top-1 must be the
// benchmark's, and every confused pair it lists is counted.
TEST(BenchDescriptors, ConfusionsScriptAgreesWithTheBenchmark) {
  if (e2e::python3().empty()) GTEST_SKIP() << "no Python 3 interpreter found by CMake";
  e2e::TempDir dir("bench_confusions");
  const std::string views = (dir.path() / "views").string(), rows = (dir.path() / "rows").string();
  const std::string out = (dir.path() / "esf.json").string();
  ASSERT_TRUE(simulate_views(views, "--objects 40 --views-per-object 3 --seed 2"));
  const auto bench = e2e::run(e2e::bin("lista-bench-descriptors") + " --views " + views +
                              " --plugins describe.esf --json " + out + " --rows " + rows + " 2>&1");
  ASSERT_EQ(bench.status, 0) << bench.output;
  const json scores = json::parse(e2e::read_file(out)).at(0);

  const auto script = e2e::run(e2e::python3() + " " + e2e::source("bench/descriptors/confusions.py") + " " + views +
                               " " + rows + "/describe.esf.csv 2>&1");
  ASSERT_EQ(script.status, 0) << script.output;
  int views_seen = 0, wrong = 0, same_class = 0;
  double top1 = -1.0;
  ASSERT_EQ(std::sscanf(script.output.c_str(), "views %d, top-1 %lf, wrong %d, of the same class %d", &views_seen,
                        &top1, &wrong, &same_class),
            4)
      << script.output;
  EXPECT_EQ(views_seen, scores.at("objects").get<int>());
  EXPECT_NEAR(top1, scores.at("top1").get<double>(), 0.0005);  // printed with three decimals
  ASSERT_GT(wrong, 0) << "ESF confuses some of 40 shapes; the pair lines need a miss to check";
  EXPECT_LE(same_class, wrong);
  // "  a -> b: n" lines: the ten most common pairs, together at most `wrong`.
  int listed = 0, n = 0;
  std::istringstream lines(script.output);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind("  ", 0) == 0 && line.find(" -> ") != std::string::npos) {
      ASSERT_EQ(std::sscanf(line.c_str() + line.rfind(':'), ": %d", &n), 1) << line;
      listed += n;
    }
  EXPECT_GT(listed, 0);
  EXPECT_LE(listed, wrong);
}
