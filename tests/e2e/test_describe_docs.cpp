// `lista-run --describe` is a summary, not a manual: every plugin's doc is a
// few lines that end by naming its section in docs/, where the explanation
// lives once. A long doc, a pointer to a page or heading that is not there,
// or version history in a doc fails here.
#include "e2e_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr size_t max_doc_chars = 600;

// Every plugin --list-plugins shows: its entries are the indented lines.
std::vector<std::string> listed_plugins() {
  const e2e::Result r = e2e::run(e2e::bin("lista-run") + " --list-plugins");
  EXPECT_EQ(r.status, 0) << r.output;
  std::vector<std::string> names;
  std::istringstream lines(r.output);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("  ", 0) != 0) continue;
    std::istringstream words(line);
    std::string name;
    if (words >> name) names.push_back(name);
  }
  return names;
}

bool has_heading_containing(const std::string& page, const std::string& text) {
  std::istringstream lines(page);
  std::string line;
  while (std::getline(lines, line))
    if (line.rfind("#", 0) == 0 && line.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(DescribeText, EveryPluginIsAShortSummaryPointingAtItsDocs) {
  const std::vector<std::string> plugins = listed_plugins();
  ASSERT_GE(plugins.size(), 20u) << "the shipped plugins were not found";
  // `docs/<page>.md`, optionally followed by `, "<heading>"`.
  const std::regex pointer(R"re((docs/[A-Za-z0-9_./-]+\.md)(, "([^"]+)")?)re");
  const std::regex version(R"(\b\d+\.\d+\.\d+\b)");
  for (const std::string& name : plugins) {
    SCOPED_TRACE(name);
    const e2e::Result r = e2e::run(e2e::bin("lista-run") + " --describe " + name + " --json");
    ASSERT_EQ(r.status, 0) << r.output;
    const auto info = nlohmann::json::parse(r.output, nullptr, false);
    ASSERT_FALSE(info.is_discarded()) << r.output;
    const std::string doc = info.value("doc", "");
    EXPECT_LE(doc.size(), max_doc_chars) << doc;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(doc, m, pointer)) << "no docs/ pointer in: " << doc;
    const fs::path page = e2e::source(m[1].str());
    ASSERT_TRUE(fs::is_regular_file(page)) << m[1].str() << " does not exist";
    if (m[3].matched) {
      EXPECT_TRUE(has_heading_containing(e2e::read_file(page), m[3].str()))
          << m[1].str() << " has no heading \"" << m[3].str() << "\"";
    }
    // Version history belongs in CHANGELOG.md, not in what --describe prints.
    EXPECT_FALSE(std::regex_search(doc, version)) << doc;
    for (const auto& p : info.value("params", nlohmann::json::array()))
      EXPECT_FALSE(std::regex_search(p.value("doc", std::string()), version)) << p.value("name", "") << ": " << p;
  }
}
