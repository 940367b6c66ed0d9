#include "make_stage.hpp"

#include <gtest/gtest.h>
#include <lista/basic_context.hpp>
#include <lista_io/pcd.hpp>
#include <lista_io/poses.hpp>

#include <filesystem>
#include <unistd.h>

using namespace lista;
namespace fs = std::filesystem;

namespace {

fs::path make_dataset(const std::string& tag) {
  const fs::path root = fs::temp_directory_path() / ("lista_io_missions_" + tag + "_" + std::to_string(::getpid()));
  fs::remove_all(root);
  for (const char* m : {"t1", "t0"}) {
    fs::create_directories(root / m / "scans");
    std::vector<io::PoseRecord> poses(2);
    for (int s = 0; s < 2; ++s) {
      PointSet p;
      for (int i = 0; i < 4; ++i) p.xyz.emplace_back(float(i), float(s), 0.f);
      io::write_scan_pcd((root / m / "scans" / ("00" + std::to_string(s) + ".pcd")).string(), p);
      poses[s].timestamp = s;
    }
    io::write_poses((root / m / "poses.txt").string(), poses);
  }
  return root;
}

}  // namespace

TEST(IoMissions, ReadsTheRunDatasetSortedOrListed) {
  const fs::path root = make_dataset("a");
  BasicContext ctx("read", 2);
  ctx.info.dataset = root.string();
  auto all = io_test::make_stage("io.missions")->run(Inputs{}, ctx);
  const auto& set = all.at("missions").as<MissionSet>();
  ASSERT_EQ(set.missions.size(), 2u);
  EXPECT_EQ(set.missions[0].name, "t0");
  EXPECT_EQ(set.missions[1].point_count(), 8u);
  EXPECT_EQ(ctx.info.metrics["read"]["points"], 16.0);

  auto listed = io_test::make_stage("io.missions", {{"path", root.string()},
                                                     {"missions", std::vector<std::string>{"t1", "t0"}}})
                    ->run(Inputs{}, ctx);
  EXPECT_EQ(listed.at("missions").as<MissionSet>().missions[0].name, "t1");
}

TEST(IoMissions, ClearErrors) {
  const fs::path root = make_dataset("b");
  BasicContext ctx;
  try {
    io_test::make_stage("io.missions")->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no dataset"), std::string::npos) << e.what();
  }
  try {
    io_test::make_stage("io.missions", {{"path", root.string()}, {"missions", std::vector<std::string>{"t9"}}})
        ->run(Inputs{}, ctx);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no mission 't9'"), std::string::npos) << e.what();
  }
}
