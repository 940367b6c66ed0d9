// Shared helpers for the core's tests: the test plugin folders and a
// registry with the good test library loaded.
#pragma once

#include <lista_core/loader.hpp>
#include <lista_core/plan.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace lista_test {

inline std::string good_dir() { return TEST_PLUGIN_GOOD_DIR; }
inline std::string bad_dir() { return TEST_PLUGIN_BAD_DIR; }
inline std::string good_library() { return good_dir() + "/liblista_test_stages.so"; }

inline lista::core::Registry& test_registry() {
  static lista::core::Registry registry = [] {
    lista::core::Registry r;
    lista::core::load_plugin_library(r, good_library());
    return r;
  }();
  return registry;
}

// Parses and plans `toml` (named "p.toml") against the test registry.
inline lista::core::Plan plan_of(const std::string& toml, lista::core::Diagnostics& d,
                                 const std::vector<std::string>& sets = {}) {
  std::vector<lista::core::Override> overrides;
  for (const auto& s : sets) overrides.push_back(lista::core::parse_override(s));
  const auto spec = lista::core::parse_pipeline_text(toml, "p.toml", d);
  return lista::core::build_plan(spec, overrides, test_registry(), d);
}

// A fresh temporary folder, removed at destruction.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    path = std::filesystem::temp_directory_path() /
           ("lista-core-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter()++));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string write(const std::string& name, const std::string& text) const {
    const auto p = path / name;
    std::ofstream(p) << text;
    return p.string();
  }
  static int& counter() {
    static int c = 0;
    return c;
  }
};

}  // namespace lista_test
