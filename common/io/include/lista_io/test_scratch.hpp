// Scratch folders for test suites: one fresh folder per name and process,
// all removed when the process exits, so suites leave nothing in /tmp.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>
#include <unistd.h>

namespace lista::io::testing {

namespace detail {
struct ScratchRegistry {
  std::vector<std::filesystem::path> dirs;
  ~ScratchRegistry() {
    std::error_code ec;
    for (const auto& d : dirs) std::filesystem::remove_all(d, ec);
  }
};
inline ScratchRegistry& scratch_registry() {
  static ScratchRegistry r;
  return r;
}
}  // namespace detail

// <tmp>/lista_<name>_<pid>, emptied now (not created); removed at exit.
inline std::filesystem::path scratch_path(const std::string& name) {
  auto& reg = detail::scratch_registry();
  const auto p = std::filesystem::temp_directory_path() / ("lista_" + name + "_" + std::to_string(::getpid()));
  std::error_code ec;
  std::filesystem::remove_all(p, ec);
  reg.dirs.push_back(p);
  return p;
}

}  // namespace lista::io::testing
