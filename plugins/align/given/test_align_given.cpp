#include <lista_testing/plugin_stage.hpp>
#include "given_transforms.hpp"

#include <gtest/gtest.h>
#include <lista/basic_context.hpp>
#include <lista_io/test_scratch.hpp>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace lista;

namespace {

Eigen::Isometry3d pose(double x, double y, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translate(Eigen::Vector3d(x, y, 0.5));
  T.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  return T;
}

MissionSet two_missions(const Eigen::Isometry3d& b_map_to_world) {
  MissionSet set;
  auto pts = std::make_shared<const PointSet>();
  for (const char* name : {"A", "B"}) {
    Mission m;
    m.name = name;
    for (int i = 0; i < 5; ++i) {
      Scan s;
      s.points = pts;
      const Eigen::Isometry3d world = pose(i, 0.3 * i * i, 0.2 * i);
      s.pose = (std::string(name) == "B" ? b_map_to_world.inverse() : Eigen::Isometry3d::Identity()) * world;
      m.poses_gt.push_back(world);
      m.scans.push_back(s);
    }
    set.missions.push_back(m);
  }
  return set;
}

Inputs inputs_of(const MissionSet& set) {
  Inputs in;
  in.set("missions", Data::make(set));
  return in;
}

}  // namespace

TEST(AlignGiven, GroundTruthRecoversMapToWorldAndSharesPoints) {
  const Eigen::Isometry3d b = pose(3, -2, 0.7);
  const MissionSet set = two_missions(b);
  BasicContext ctx("align");
  auto out = plugin_test::make_stage("align.given", {{"mode", std::string("ground-truth")}})->run(inputs_of(set), ctx);
  const auto& aligned = out.at("missions").as<MissionSet>();
  EXPECT_TRUE(aligned.missions[0].to_common.isApprox(Eigen::Isometry3d::Identity(), 1e-9));
  EXPECT_TRUE(aligned.missions[1].to_common.isApprox(b, 1e-9));
  EXPECT_EQ(aligned.missions[1].scans[0].points.get(), set.missions[1].scans[0].points.get());
  EXPECT_LT(ctx.info.metrics["align"]["B.fit_rmse_m"], 1e-9);
}

TEST(AlignGiven, GroundTruthPosesTakeTheDriftOut) {
  const Eigen::Isometry3d b = pose(3, -2, 0.7);
  MissionSet set = two_missions(b);
  // Drift: B's later scans wander off their true poses.
  for (size_t i = 0; i < set.missions[1].scans.size(); ++i)
    set.missions[1].scans[i].pose.translation() += Eigen::Vector3d(0.05 * i, -0.03 * i, 0.0);
  for (const char* mode : {"ground-truth", "ground-truth-poses"}) {
    BasicContext ctx("align");
    auto out = plugin_test::make_stage("align.given", {{"mode", std::string(mode)}})->run(inputs_of(set), ctx);
    const Mission& m = out.at("missions").as<MissionSet>().missions[1];
    double worst = 0;
    for (size_t i = 0; i < m.scans.size(); ++i)
      worst = std::max(worst, (m.sensor_to_common(i).matrix() - m.poses_gt[i].matrix()).cwiseAbs().maxCoeff());
    if (std::string(mode) == "ground-truth") EXPECT_GT(worst, 0.05) << "the rigid fit cannot remove drift";
    else EXPECT_LT(worst, 1e-9) << "every scan at its true pose";
    EXPECT_GT(ctx.info.metrics["align"]["B.fit_rmse_m"], 0.01);
  }
}

TEST(AlignGiven, SingleScanIsEnoughBecauseRotationsCount) {
  MissionSet set = two_missions(pose(1, 2, -1.0));
  for (auto& m : set.missions) {
    m.scans.resize(1);
    m.poses_gt.resize(1);
  }
  EXPECT_TRUE(align::map_to_world_from_gt(set.missions[1]).isApprox(pose(1, 2, -1.0), 1e-9));
  set.missions[0].poses_gt.clear();
  EXPECT_THROW(align::map_to_world_from_gt(set.missions[0]), Error);
}

TEST(AlignGiven, FileModeAndItsErrors) {
  const auto dir = io::testing::scratch_path("align_given");
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "t.txt").string();
  std::ofstream(path) << "# mission  4x4\nA 1 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1\nB 0 -1 0 2  1 0 0 3  0 0 1 4\n";
  BasicContext ctx;
  auto out = plugin_test::make_stage("align.given", {{"mode", std::string("file")}, {"file", path}})
                 ->run(inputs_of(two_missions(Eigen::Isometry3d::Identity())), ctx);
  const auto& b = out.at("missions").as<MissionSet>().missions[1].to_common;
  EXPECT_EQ(b.translation(), Eigen::Vector3d(2, 3, 4));
  EXPECT_TRUE(b.rotation().isApprox(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix()));

  std::ofstream(path) << "A 1 0 0 0  0 1 0 0  0 0 1 0\n";
  try {
    plugin_test::make_stage("align.given", {{"mode", std::string("file")}, {"file", path}})
        ->run(inputs_of(two_missions(Eigen::Isometry3d::Identity())), ctx);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no transform for mission 'B'"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "A 1 0 0 0  0 1 0 0  0 0 1\nB 2 0 0 0 0 1 0 0 0 0 1 0\n";
  try {
    align::read_transform_file(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.txt:1: expected a mission name and 16"), std::string::npos) << e.what();
  }
  std::ofstream(path) << "A 1 0 0 0  0 1 0 0  0 0 1 0\nB 2 0 0 0 0 1 0 0 0 0 1 0\n";
  try {
    align::read_transform_file(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("t.txt:2: rotation of 'B' is not orthonormal"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(plugin_test::make_stage("align.given", {{"mode", std::string("file")}}), Error);
  EXPECT_THROW(plugin_test::make_stage("align.given", {{"mode", std::string("magic")}}), Error);
}

TEST(AlignGiven, IdentityModeResetsEveryMissionAndKeepsPoses) {
  MissionSet set = two_missions(pose(3, -2, 0.7));
  set.missions[1].to_common = pose(1, 1, 1.0);  // e.g. left over from an earlier alignment
  BasicContext ctx;
  auto out = plugin_test::make_stage("align.given")->run(inputs_of(set), ctx);  // default mode: identity
  const auto& aligned = out.at("missions").as<MissionSet>();
  ASSERT_EQ(aligned.missions.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(aligned.missions[k].to_common.isApprox(Eigen::Isometry3d::Identity(), 1e-12));
    EXPECT_TRUE(aligned.missions[k].scans[3].pose.isApprox(set.missions[k].scans[3].pose, 1e-12));
  }
}
