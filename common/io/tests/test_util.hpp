// Shared helpers for the lista_io tests: a fresh temp folder per test.
#pragma once

#include <gtest/gtest.h>
#include <lista/error.hpp>
#include <lista_io/test_scratch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace lista_io_test {

inline std::filesystem::path temp_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string leaf = "io_" + name + "_" + info->test_suite_name() + "_" + info->name();
  for (char& c : leaf)
    if (c == '/') c = '_';  // parameterised tests: "Suite/Param", one folder level only
  auto dir = lista::io::testing::scratch_path(leaf);
  std::filesystem::create_directories(dir);
  return dir;
}

inline void write_text(const std::filesystem::path& p, const std::string& s) {
  std::ofstream(p, std::ios::binary) << s;
}

// Asserts that fn throws lista::Error whose message contains `needle`.
template <class Fn>
void expect_error(Fn fn, const std::string& needle) {
  try {
    fn();
    ADD_FAILURE() << "no error thrown, expected one containing '" << needle << "'";
  } catch (const lista::Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

}  // namespace lista_io_test
