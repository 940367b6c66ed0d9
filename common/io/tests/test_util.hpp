// Shared helpers for the lista_io tests: a fresh temp folder per test.
#pragma once

#include <gtest/gtest.h>
#include <lista/error.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace lista_io_test {

inline std::filesystem::path temp_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  auto dir = std::filesystem::temp_directory_path() /
             ("lista_io_" + name + "_" + info->test_suite_name() + "_" + info->name() + "_" +
              std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
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
