// Plugin loading: a real plugin library, and each way a library can be refused.
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <memory>

using namespace lista::core;
using lista_test::bad_dir;
using lista_test::good_dir;

namespace {

std::string load_error(const std::string& file) {
  Registry r;
  try {
    load_plugin_library(r, file);
  } catch (const lista::Error& e) {
    EXPECT_EQ(r.size(), 0u) << "a refused library must register nothing";
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Loader, LoadsTheTestLibraryAndItsDeclarations) {
  Registry r;
  load_plugin_library(r, lista_test::good_library());
  const RegisteredStage* s = r.find("test.source");
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->info.kind(), "test");
  EXPECT_NE(s->library.find("liblista_test_stages.so"), std::string::npos);
  ASSERT_NE(s->info.param("scale"), nullptr);
  EXPECT_EQ(s->info.param("scale")->unit_label, "m");
  EXPECT_GE(r.size(), 7u);
  // Loading the same file again is harmless.
  load_plugin_library(r, lista_test::good_library());
  EXPECT_GE(r.size(), 7u);
}

// A registry knows what it holds itself: a new registry that happens to get
// the address of a destroyed one still gets every stage.
TEST(Loader, EveryNewRegistryGetsTheStages) {
  for (int i = 0; i < 3; ++i) {
    auto r = std::make_unique<Registry>();
    load_plugin_library(*r, lista_test::good_library());
    EXPECT_NE(r->find("test.source"), nullptr) << "registry " << i;
  }
}

TEST(Loader, UndefinedSymbolNamesFileAndSymbol) {
  const std::string e = load_error(bad_dir() + "/liblista_test_broken_symbol.so");
  EXPECT_NE(e.find("liblista_test_broken_symbol.so"), std::string::npos) << e;
  EXPECT_NE(e.find("undefined symbol"), std::string::npos) << e;
  EXPECT_NE(e.find("lista_test_symbol_that_does_not_exist"), std::string::npos) << e;
  EXPECT_NE(e.find("cannot load plugin library: undefined symbol"), std::string::npos) << e;  // the path once
}

// A missing lista:: symbol means other SDK headers or another string ABI:
// the loader says so, since the fingerprint check never gets to run.
TEST(Loader, MissingSdkSymbolSaysToRebuildAgainstThisLista) {
  const std::string e = load_error(bad_dir() + "/../oldsdk/liblista_test_old_sdk.so");
  EXPECT_NE(e.find("undefined symbol: _ZN5lista"), std::string::npos) << e;
  EXPECT_NE(e.find("a LiSTA SDK symbol this core does not have"), std::string::npos) << e;
  EXPECT_NE(e.find("-D_GLIBCXX_USE_CXX11_ABI=0"), std::string::npos) << e;
}

TEST(Loader, LibraryWithoutManifestIsRefused) {
  const std::string e = load_error(bad_dir() + "/liblista_test_no_manifest.so");
  EXPECT_NE(e.find("liblista_test_no_manifest.so"), std::string::npos) << e;
  EXPECT_NE(e.find("not a LiSTA plugin"), std::string::npos) << e;
}

TEST(Loader, AbiMismatchIsRefusedBeforeRegistration) {
  // The library's register function aborts: reaching it would kill the test.
  const std::string e = load_error(bad_dir() + "/liblista_test_abi_mismatch.so");
  EXPECT_NE(e.find("bogus"), std::string::npos) << e;
  EXPECT_NE(e.find(LISTA_BUILD_FINGERPRINT), std::string::npos) << e;
  EXPECT_NE(e.find("ABI mismatch"), std::string::npos) << e;
}

TEST(Loader, MissingFileIsAnError) {
  const std::string e = load_error("/nonexistent/libnothing.so");
  EXPECT_NE(e.find("/nonexistent/libnothing.so"), std::string::npos) << e;
}

TEST(Loader, DuplicateNameNamesBothLibraries) {
  Registry r;
  load_plugin_library(r, lista_test::good_library());
  try {
    load_plugin_library(r, TEST_PLUGIN_DUP_DIR "/liblista_test_duplicate.so");
    FAIL() << "duplicate accepted";
  } catch (const lista::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test.source"), std::string::npos) << m;
    EXPECT_NE(m.find("liblista_test_stages.so"), std::string::npos) << m;
    EXPECT_NE(m.find("liblista_test_duplicate.so"), std::string::npos) << m;
  }
  EXPECT_EQ(r.find("test.source")->info.version, "1.0.0");  // the first one stays
  ASSERT_EQ(r.refused("test.source").size(), 1u);
  EXPECT_NE(r.refused("test.source")[0].find("liblista_test_duplicate.so"), std::string::npos);
  // A pipeline that uses the name is told which library it gets.
  Diagnostics d;
  build_plan(parse_pipeline_text("[stages.src]\nplugin = \"test.source\"\n", "p.toml", d), {}, r, d);
  ASSERT_TRUE(d.ok());
  ASSERT_EQ(d.warnings.size(), 2u);  // and that its output is not used
  const std::string w = d.warnings[0].str() + d.warnings[1].str();
  EXPECT_NE(w.find("plugin 'test.source' is provided twice: using "), std::string::npos) << w;
  EXPECT_NE(w.find("liblista_test_stages.so (found first on the plugin search path), not "), std::string::npos) << w;
}

// A declaration that cannot be right is refused when it registers, naming
// the stage and the fault, rather than misbehaving in a pipeline later.
TEST(Registry, RefusesDeclarationsThatDoNotHoldTogether) {
  auto factory = [](const lista::Params&) -> std::unique_ptr<lista::Stage> { return nullptr; };
  auto base = [] {
    lista::StageInfo i;
    i.name = "mine.stage";
    i.inputs = {{"objects", "objects", ""}};
    i.outputs = {{"descriptors", "descriptors", ""}};
    i.params = {lista::ParamSpec::integer("bins", 8, "").range(2, 64)};
    return i;
  };
  std::vector<std::pair<std::function<void(lista::StageInfo&)>, std::string>> cases = {
      {[](lista::StageInfo& i) { i.params.push_back(lista::ParamSpec::integer("bins", 16, "")); },
       "stage 'mine.stage' declares parameter 'bins' twice"},
      {[](lista::StageInfo& i) { i.params.push_back(lista::ParamSpec::real("weight", 50.0, "").range(0, 10)); },
       "parameter 'weight': its default must be in [0.0, 10.0], got 50.0"},
      {[](lista::StageInfo& i) { i.name = "Decl.Weird Name!"; },
       "stage name 'Decl.Weird Name!' from the program itself is not of the form <kind>.<name>"},
      {[](lista::StageInfo& i) { i.name = "nodot"; }, "stage name 'nodot' from the program itself is not of the form"},
      {[](lista::StageInfo& i) { i.params.push_back(lista::ParamSpec::integer("n", 5, "").range(10, 1)); },
       "parameter 'n': its range [10, 1] is empty (lower bound above upper)"},
      {[](lista::StageInfo& i) { i.params.push_back(lista::ParamSpec::text("mode", "x", "").one_of({"a", "b"})); },
       "parameter 'mode': its default must be one of"},
      {[](lista::StageInfo& i) { i.outputs[0].type = "descriptor"; },
       "output 'descriptors' has type 'descriptor', which is not a port type (missions, points, objects"},
      {[](lista::StageInfo& i) { i.inputs.push_back({"objects", "objects", ""}); },
       "declares input 'objects' twice"},
  };
  {
    Registry r;
    EXPECT_NO_THROW(r.add(base(), factory));
  }
  for (const auto& [spoil, text] : cases) {
    Registry r;
    lista::StageInfo info = base();
    spoil(info);
    try {
      r.add(info, factory);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const lista::Error& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
    EXPECT_EQ(r.find("mine.stage"), nullptr);
  }
}

TEST(Loader, FolderLoadCollectsEveryFailureAndSkipsMissingFolders) {
  Registry r;
  const LoadResult res = load_plugins(r, {"/nonexistent/folder", bad_dir(), good_dir()});
  EXPECT_EQ(res.loaded.size(), 1u);
  EXPECT_EQ(res.errors.size(), 3u);
  EXPECT_NE(r.find("test.join"), nullptr);
}

TEST(Loader, OnlyLibSoFilesAreConsidered) {
  lista_test::TempDir dir;
  dir.write("notes.txt", "x");
  dir.write("libfake.so.txt", "x");
  dir.write("plugin.so", "not an elf");  // no lib prefix: ignored
  dir.write("libjunk.so", "not an elf");  // considered, and refused
  Registry r;
  const LoadResult res = load_plugins(r, {dir.path.string()});
  ASSERT_EQ(res.errors.size(), 1u);
  EXPECT_NE(res.errors[0].find("libjunk.so"), std::string::npos);
}

TEST(Loader, SearchPathOrder) {
  setenv("LISTA_PLUGIN_PATH", "/a::/b", 1);
  const auto dirs = plugin_search_path({"/c"}, true);
  unsetenv("LISTA_PLUGIN_PATH");
  ASSERT_EQ(dirs.size(), 4u);
  EXPECT_EQ(dirs[0], "/a");
  EXPECT_EQ(dirs[1], "/b");
  EXPECT_EQ(dirs[2], "/c");
  EXPECT_NE(dirs[3].find("lista-plugins"), std::string::npos);
  EXPECT_EQ(plugin_search_path({"/c"}, false).size(), 1u);
}
