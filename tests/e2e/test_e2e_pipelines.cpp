// Every shipped pipeline validates against the plugins as built: a renamed
// parameter, port or plugin breaks this test, not a user's run.
#include "e2e_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
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
  for (const fs::path& file : shipped_pipelines()) {
    SCOPED_TRACE(file.string());
    const e2e::Result r = e2e::run(e2e::bin("lista-run") + " '" + file.string() + "' --validate 2>&1");
    EXPECT_EQ(r.status, 0) << r.output;
    const auto first = r.output.find('{');
    ASSERT_NE(first, std::string::npos) << r.output;
    const auto verdict = nlohmann::json::parse(r.output.substr(first), nullptr, false);
    ASSERT_FALSE(verdict.is_discarded()) << r.output;
    EXPECT_TRUE(verdict.value("valid", false)) << r.output;
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
