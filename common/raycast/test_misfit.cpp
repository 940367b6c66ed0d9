// The alignment's misfit, measured where two missions hold the same wall,
// and the neighbourhood a pair is then judged with: a wall left two voxels
// apart is not change, a pair that fits keeps the configured neighbourhood.
#include <lista_raycast/misfit.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace lista;

namespace {

// A room seen from the origin: its far wall at voxel x = `wall` (y 0-99,
// z 0-59) occupied, the space before it free; with `box`, a box (x 100-103,
// y 40-43, z 0-9) occupied in it.
class RoomMap : public raycast::OccupancyMap {
 public:
  RoomMap(int wall, bool box) : wall_(wall), box_(box) {}
  std::unique_ptr<raycast::OccupancyReader> reader() const override {
    struct Reader : raycast::OccupancyReader {
      int wall;
      bool box;
      bool logodds(const raycast::Voxel& v, float& out) override {
        if (v.x() < 0 || v.x() > wall || v.y() < 0 || v.y() >= 100 || v.z() < 0 || v.z() >= 60) return false;
        const bool in_box = box && v.x() >= 100 && v.x() < 104 && v.y() >= 40 && v.y() < 44 && v.z() < 10;
        out = v.x() == wall || in_box ? 5.f * raycast::logodds(0.7) : 5.f * raycast::logodds(0.4);
        return true;
      }
    };
    auto r = std::make_unique<Reader>();
    r->wall = wall_;
    r->box = box_;
    return r;
  }

 private:
  int wall_;
  bool box_;
};

// A mission of one scan, its sensor at the origin, holding `points`.
Mission one_scan(const std::string& name, std::vector<Eigen::Vector3f> points) {
  auto set = std::make_shared<PointSet>();
  for (const auto& p : points) {
    set->xyz.push_back(p);
    set->scan.push_back(0);
    set->index.push_back(uint32_t(set->index.size()));
  }
  Mission m;
  m.name = name;
  Scan scan;
  scan.points = set;
  m.scans.push_back(scan);
  return m;
}

// Points on the wall x = 10.025 m + shift (5 cm voxels: the centres of
// the voxels x = 200), off the voxel grid in y and z.
Mission wall_mission(double shift) {
  std::vector<Eigen::Vector3f> points;
  for (int y = 5; y < 95; y += 2)
    for (int z = 5; z < 55; z += 2)
      points.emplace_back(float(10.025 + shift), float(0.05 * y + 0.013), float(0.05 * z + 0.021));
  return one_scan("A", points);
}

// One scan from the origin holding the room's wall at voxel x `wall` and,
// with `box`, the box's face: points at the voxels' centres.
Mission room_mission(const std::string& name, int wall, bool box) {
  std::vector<Eigen::Vector3f> points;
  auto add = [&](int x, int y, int z) {
    points.emplace_back(0.05f * float(x) + 0.025f, 0.05f * float(y) + 0.025f, 0.05f * float(z) + 0.025f);
  };
  for (int y = 0; y < 100; ++y)
    for (int z = 0; z < 60; ++z) add(wall, y, z);
  if (box)
    for (int y = 40; y < 44; ++y)
      for (int z = 0; z < 10; ++z) add(100, y, z);
  return one_scan(name, points);
}

}  // namespace

TEST(Misfit, AWallHeldWhereTheOtherHoldsItFits) {
  const raycast::VolumetricConfig config;  // 5 cm voxels, neighbourhood 1
  const double misfit = raycast::surface_misfit(wall_mission(0.0), RoomMap(200, false), config);
  EXPECT_LT(misfit, 0.3);
  EXPECT_EQ(raycast::pair_neighbourhood(misfit, config.neighbourhood), config.neighbourhood);
}

TEST(Misfit, AWallTwoVoxelsOffWidensTheNeighbourhoodPastIt) {
  const raycast::VolumetricConfig config;
  const double misfit = raycast::surface_misfit(wall_mission(0.1), RoomMap(200, false), config);
  EXPECT_NEAR(misfit, 2.0, 0.2);
  EXPECT_GE(raycast::pair_neighbourhood(misfit, config.neighbourhood), 3);
  // A shift of a quarter voxel is what quantisation alone gives: no change.
  EXPECT_EQ(raycast::pair_neighbourhood(raycast::surface_misfit(wall_mission(0.0125), RoomMap(200, false), config), 1), 1);
}

TEST(Misfit, NoSharedSurfaceMeasuresNothing) {
  // Points 3 m behind the other's wall: no plane near them, misfit 0.
  const raycast::VolumetricConfig config;
  EXPECT_EQ(raycast::surface_misfit(wall_mission(3.0), RoomMap(200, false), config), 0.0);
}

TEST(Misfit, AWallTheAlignmentLeftApartIsNotChangeAndTheRemovedBoxStillIs) {
  // A holds the wall two voxels nearer than B (a 10 cm misfit) and a box B
  // no longer has. With the configured neighbourhood of one voxel the whole
  // wall would be change; the pair's measured misfit widens it.
  MissionSet set;
  set.missions = {room_mission("A", 198, true), room_mission("B", 200, false)};
  const RoomMap a(198, true), b(200, false);
  raycast::ChangeStats stats;
  const MissionPoints got = raycast::detect_changes(set, {&a, &b}, raycast::VolumetricConfig{}, 2, &stats);
  ASSERT_EQ(got.sets.size(), 2u);
  EXPECT_EQ(got.sets[0].size(), 40u) << "the box's face, not the wall";
  for (const auto& p : got.sets[0].xyz) EXPECT_LT(p.x(), 5.1f);
  ASSERT_EQ(stats.misfit.size(), 1u);
  EXPECT_NEAR(stats.misfit[0], 0.1, 0.01);
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_NE(stats.warnings[0].find("check the alignment"), std::string::npos) << stats.warnings[0];
}

TEST(Misfit, APairThatFitsIsJudgedAsConfigured) {
  MissionSet set;
  set.missions = {room_mission("A", 200, true), room_mission("B", 200, false)};
  const RoomMap a(200, true), b(200, false);
  raycast::ChangeStats stats;
  const MissionPoints got = raycast::detect_changes(set, {&a, &b}, raycast::VolumetricConfig{}, 2, &stats);
  EXPECT_EQ(got.sets[0].size(), 40u);
  EXPECT_TRUE(stats.warnings.empty());
  EXPECT_LT(stats.misfit[0], 0.015);
}
