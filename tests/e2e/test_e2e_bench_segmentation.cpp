// lista-bench segmentation on bad input: a value that would crash or exhaust
// memory (--repeat 0, --spacing 0) and a malformed --changes cloud are each
// one line of error and a non-zero exit, never an abort.
#include "e2e_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

TEST(BenchSegmentation, BadArgumentsAndCloudsAreOneLineOfError) {
  const std::string prog = e2e::bin("lista-bench-segmentation");
  for (const char* args : {"--repeat 0", "--spacing 0", "--spacing -1", "--tolerance 0", "--objects -5", "--missions 0"}) {
    const auto r = e2e::run(prog + " --no-mls " + args + " 2>&1");
    EXPECT_EQ(r.status, 2) << args << ": " << r.output;
    EXPECT_EQ(r.output.find("lista-bench segmentation: error: --"), 0u) << r.output;
    EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
  }
  e2e::TempDir dir("bench-seg");
  std::ofstream(dir.path() / "A.pcd") << "VERSION 0.7\nFIELDS x y z\nSIZE 2 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                                         "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n";
  const auto r = e2e::run(prog + " --no-mls --changes " + dir.path().string() + " 2>&1");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("lista-bench segmentation: error: " + (dir.path() / "A.pcd").string()), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << "one line: " << r.output;
}
