// Every shipped pipeline validates against the plugins as built: a renamed
// parameter, port or plugin breaks this test, not a user's run.
#include "e2e_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <toml.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> shipped_pipelines() {
  std::vector<fs::path> files;
  for (const char* dir : {"pipelines", "pipelines/ablations"})
    for (const auto& e : fs::directory_iterator(e2e::source(dir)))
      if (e.path().extension() == ".toml") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST(Pipelines, TheDefaultAndTheAblationsAreShipped) {
  const auto files = shipped_pipelines();
  EXPECT_TRUE(std::count(files.begin(), files.end(), fs::path(e2e::source("pipelines/lista.toml"))));
  EXPECT_GE(files.size(), 9u);  // lista.toml and at least eight ablations
}

TEST(Pipelines, EveryShippedPipelineValidates) {
  // A file naming its dataset (demo.toml: data/demo, made by ./setup.sh demo)
  // is checked against an empty stand-in: a clean clone has no data/.
  const e2e::TempDir dataset("validate-dataset");
  for (const fs::path& file : shipped_pipelines()) {
    SCOPED_TRACE(file.string());
    const toml::value pipeline = toml::parse(file.string());
    const bool names_dataset = pipeline.contains("pipeline") && pipeline.at("pipeline").contains("dataset");
    const std::string stand_in = names_dataset ? " --dataset '" + dataset.path().string() + "'" : "";
    const e2e::Result r = e2e::run(e2e::bin("lista-run") + " '" + file.string() + "'" + stand_in + " --validate 2>&1");
    EXPECT_EQ(r.status, 0) << r.output;
    const auto first = r.output.find('{');
    ASSERT_NE(first, std::string::npos) << r.output;
    const auto verdict = nlohmann::json::parse(r.output.substr(first), nullptr, false);
    ASSERT_FALSE(verdict.is_discarded()) << r.output;
    EXPECT_TRUE(verdict.value("valid", false)) << r.output;
    // Shipped files speak the current names: no renamed parameter's warning.
    EXPECT_EQ(r.output.find("is now"), std::string::npos) << r.output;
  }
}

// A pipeline written with the flat names of before the parameter groups
// (and the sentinels they had) still validates and runs as it did, with one
// warning per old name that names the new spelling.
TEST(Pipelines, OldParameterNamesStillValidateWithAWarning) {
  std::string text = e2e::read_file(e2e::source("pipelines/lista.toml"));
  const auto after = [&](const std::string& line, const std::string& insert) {
    const auto at = text.find(line);
    ASSERT_NE(at, std::string::npos) << line;
    text.insert(at + line.size(), insert);
  };
  after("plugin = \"align.posegraph\"\n", "scan_points = 12000\nsolver_iterations = 80\nscan_disagreement = 0\n");
  after("plugin = \"match.weighted\"\n", "max_tilt = 180\nmax_cost = -1\ngroup_mode = \"hard\"\nmin_shape_fit = 0.7\n");
  const e2e::TempDir dir("old-names");
  const std::string file = (dir.path() / "old-names.toml").string();
  std::ofstream(file) << text;
  const e2e::Result r = e2e::run(e2e::bin("lista-run") + " '" + file + "' --validate 2>&1");
  EXPECT_EQ(r.status, 0) << r.output;
  const auto verdict = nlohmann::json::parse(r.output.substr(r.output.find('{')), nullptr, false);
  ASSERT_FALSE(verdict.is_discarded()) << r.output;
  EXPECT_TRUE(verdict.value("valid", false)) << r.output;
  std::vector<std::string> warnings;
  for (const auto& w : verdict.at("warnings")) warnings.push_back(w.at("message").get<std::string>());
  for (const char* said :
       {"parameter 'scan_points' is now 'scans.points' (the old name works until the next release)",
        "parameter 'solver_iterations' is now 'graph.iterations'",
        "parameter 'scan_disagreement' is now 'scans.disagreement' (the old name works until the next release); 0 reads "
        "as scans.check_disagreement = false",
        "parameter 'max_tilt' is now 'floor_gate.max_tilt' (the old name works until the next release); 180 reads as "
        "floor_gate.check_tilt = false",
        "parameter 'max_cost' is now 'cost_gate.max_cost' (the old name works until the next release); -1 reads as "
        "cost_gate.automatic = true",
        "parameter 'group_mode' is now 'groups.mode'", "parameter 'min_shape_fit' is now 'shape_gate.min_fit'"})
    EXPECT_EQ(std::count_if(warnings.begin(), warnings.end(),
                            [&](const std::string& w) { return w.rfind(said, 0) == 0; }),
              1)
        << said << "\n" << r.output;
  // The values arrive under the new names.
  const e2e::Result plan = e2e::run(e2e::bin("lista-run") + " '" + file + "' --dry-run 2>/dev/null");
  EXPECT_EQ(plan.status, 0) << plan.output;
  for (const char* line : {"param  scans.points = 12000\n", "param  graph.iterations = 80\n",
                           "param  scans.check_disagreement = false\n", "param  floor_gate.check_tilt = false\n",
                           "param  cost_gate.automatic = true\n", "param  groups.mode = \"hard\"\n",
                           "param  shape_gate.enabled = true\n", "param  shape_gate.min_fit = 0.7\n"})
    EXPECT_NE(plan.output.find(line), std::string::npos) << line << plan.output;
}

// The ablations, the demo and the example are full copies of lista.toml
// (the format has no include). Each may differ from it only in the stages
// it is about: a change to the default pipeline not carried into a copy
// fails here, not as an ablation quietly measuring an older pipeline.
TEST(Pipelines, CopiesDifferFromTheDefaultOnlyInTheirOwnStages) {
  const std::map<std::string, std::set<std::string>> own = {
      {"pipelines/demo.toml", {}},
      {"pipelines/ablations/align-ground-truth.toml", {"align"}},
      {"pipelines/ablations/align-icp.toml", {"align"}},
      {"pipelines/ablations/align-pcl-gicp.toml", {"align"}},
      {"pipelines/ablations/describe-esf.toml", {"describe"}},
      {"pipelines/ablations/describe-rift.toml", {"describe"}},
      {"pipelines/ablations/describe-shot.toml", {"describe"}},
      {"pipelines/ablations/diff-paper.toml", {"diff"}},
      {"pipelines/ablations/group-agglomerative.toml", {"group"}},
      {"pipelines/ablations/match-paper.toml", {"match"}},
      {"pipelines/ablations/history-off.toml", {"history", "report", "html"}},  // report reads comove, group, refine
      {"pipelines/ablations/register-svd.toml", {"refine", "history"}},  // no refine: history reads register
      {"pipelines/ablations/volumetric-octomap.toml", {"diff"}},
      {"examples/describe-extent/pipeline.toml", {"describe"}},
  };
  std::vector<fs::path> copies = shipped_pipelines();
  for (const auto& e : fs::directory_iterator(e2e::source("examples")))
    if (fs::exists(e.path() / "pipeline.toml")) copies.push_back(e.path() / "pipeline.toml");
  for (const fs::path& file : copies) {
    const std::string rel = fs::relative(file, e2e::source(".")).string();
    if (rel != "pipelines/lista.toml") {
      EXPECT_TRUE(own.count(rel)) << rel << ": a new copy, list the stages it changes here";
    }
  }
  const toml::value base = toml::parse(e2e::source("pipelines/lista.toml"));
  const toml::table& base_stages = toml::find<toml::table>(base, "stages");
  const toml::table& base_header = toml::find<toml::table>(base, "pipeline");
  for (const auto& [rel, expected] : own) {
    SCOPED_TRACE(rel);
    const toml::value copy = toml::parse(e2e::source(rel));
    // [pipeline]: its own name and folders, the default's seed and threads.
    const toml::table& header = toml::find<toml::table>(copy, "pipeline");
    for (const char* key : {"seed", "threads"})
      EXPECT_EQ(header.count(key) ? toml::format(header.at(key)) : "", base_header.count(key) ? toml::format(base_header.at(key)) : "")
          << key;
    const toml::table& stages = toml::find<toml::table>(copy, "stages");
    std::set<std::string> differ;
    for (const auto& [id, table] : base_stages) {
      const auto it = stages.find(id);
      if (it == stages.end() || !(it->second == table)) differ.insert(id);
    }
    for (const auto& [id, table] : stages)
      if (!base_stages.count(id)) differ.insert(id);
    EXPECT_EQ(differ, expected);
  }
}

// Every program and library of the build tree finds the LiSTA libraries
// next to itself ($ORIGIN RUNPATHs): a build tree copied elsewhere runs its
// own code, never the libraries of the tree it was built in.
TEST(BuildTree, ProgramsFindTheirLibrariesNextToThemselves) {
  namespace fs = std::filesystem;
  const fs::path bin_dir = fs::path(e2e::bin("lista-run")).parent_path();
  const fs::path build = bin_dir.parent_path();
  size_t checked = 0;
  for (const fs::path& dir : {bin_dir, build / "lib", build / "lib" / "lista-plugins"})
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (!entry.is_regular_file() || (name.rfind("lista", 0) != 0 && name.rfind("liblista", 0) != 0)) continue;
      const auto r = e2e::run("readelf -d '" + entry.path().string() + "' 2>&1");
      ASSERT_EQ(r.status, 0) << r.output;
      for (size_t at = r.output.find("path: ["); at != std::string::npos; at = r.output.find("path: [", at + 1)) {
        const std::string paths = r.output.substr(at + 7, r.output.find(']', at) - at - 7);
        EXPECT_EQ(paths.find(build.string()), std::string::npos) << name << " has an absolute RUNPATH: " << paths;
      }
      ++checked;
    }
  EXPECT_GT(checked, 10u);
}
