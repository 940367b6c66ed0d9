// The alignment's misfit, measured where two missions hold the same wall,
// and the neighbourhood a pair is then judged with: a wall left two voxels
// apart is not change, a pair that fits keeps the configured neighbourhood.
#include <lista_raycast/misfit.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace lista;

namespace {

// A room seen from the origin: its far wall at voxel x = `wall` (y 0-199,
// z 0-59) occupied, the space before it free; with `box`, a box (x 100-103,
// y 40-43, z 0-9) occupied in it. `bent`: the wall from y = 120 (6 m, the
// fourth misfit region of 2 m) on stands at x = `bent` instead (a map a
// drift bent).
class RoomMap : public raycast::OccupancyMap {
 public:
  RoomMap(int wall, bool box, int bent = -1) : wall_(wall), box_(box), bent_(bent < 0 ? wall : bent) {}
  std::unique_ptr<raycast::OccupancyReader> reader() const override {
    struct Reader : raycast::OccupancyReader {
      int straight, bent;
      bool box;
      bool logodds(const raycast::Voxel& v, float& out) override {
        const int wall = v.y() >= 120 ? bent : straight;
        if (v.x() < 0 || v.x() > wall || v.y() < 0 || v.y() >= 200 || v.z() < 0 || v.z() >= 60) return false;
        const bool in_box = box && v.x() >= 100 && v.x() < 104 && v.y() >= 40 && v.y() < 44 && v.z() < 10;
        out = v.x() == wall || in_box ? 5.f * raycast::logodds(0.7) : 5.f * raycast::logodds(0.4);
        return true;
      }
    };
    auto r = std::make_unique<Reader>();
    r->straight = wall_;
    r->bent = bent_;
    r->box = box_;
    return r;
  }

 private:
  int wall_;
  bool box_;
  int bent_;
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

// One scan from the origin holding the room's wall at voxel x `wall` (from
// y = 120 on at `bent`, if given) and, with `box`, the box's face: points at
// the voxels' centres.
Mission room_mission(const std::string& name, int wall, bool box, int bent = -1) {
  std::vector<Eigen::Vector3f> points;
  auto add = [&](int x, int y, int z) {
    points.emplace_back(0.05f * float(x) + 0.025f, 0.05f * float(y) + 0.025f, 0.05f * float(z) + 0.025f);
  };
  for (int y = 0; y < 200; ++y)
    for (int z = 0; z < 60; ++z) add(y >= 120 && bent >= 0 ? bent : wall, y, z);
  if (box)
    for (int y = 40; y < 44; ++y)
      for (int z = 0; z < 10; ++z) add(100, y, z);
  return one_scan(name, points);
}

}  // namespace

TEST(Misfit, AWallHeldWhereTheOtherHoldsItFits) {
  const raycast::VolumetricConfig config;  // 5 cm voxels, neighbourhood 1
  const double misfit = raycast::surface_misfit(wall_mission(0.0), RoomMap(200, false), config, 2.0).overall;
  EXPECT_LT(misfit, 0.3);
  EXPECT_EQ(raycast::pair_neighbourhood(misfit, config.neighbourhood), config.neighbourhood);
}

TEST(Misfit, AWallTwoVoxelsOffWidensTheNeighbourhoodPastIt) {
  const raycast::VolumetricConfig config;
  const double misfit = raycast::surface_misfit(wall_mission(0.1), RoomMap(200, false), config, 2.0).overall;
  EXPECT_NEAR(misfit, 2.0, 0.2);
  EXPECT_GE(raycast::pair_neighbourhood(misfit, config.neighbourhood), 3);
  // A shift of a quarter voxel is what quantisation alone gives: no change.
  EXPECT_EQ(raycast::pair_neighbourhood(raycast::surface_misfit(wall_mission(0.0125), RoomMap(200, false), config, 2.0).overall, 1), 1);
}

TEST(Misfit, NoSharedSurfaceMeasuresNothing) {
  // Points 3 m behind the other's wall: no plane near them, misfit 0.
  const raycast::VolumetricConfig config;
  EXPECT_EQ(raycast::surface_misfit(wall_mission(3.0), RoomMap(200, false), config, 2.0).overall, 0.0);
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

TEST(Misfit, ARegionTheAlignmentLeftApartIsNotChangeWhereTheRestFits) {
  // B's wall stands two voxels nearer than A's from y = 6 m on (its map bent
  // there), two fifths of the wall: the pair's median fits, the regions
  // past 6 m do not, and only they are judged wider.
  const raycast::VolumetricConfig config;
  const raycast::SurfaceMisfit b_to_a =
      raycast::surface_misfit(room_mission("B", 200, false, 198), RoomMap(200, true), config, 2.0);
  EXPECT_LT(b_to_a.overall, 0.3);
  ASSERT_EQ(b_to_a.regions.size(), 5u);  // x 10-12 m by y 0-6 m, the bend at x 8-10 m by y 6-10 m
  for (int y = 0; y < 3; ++y) EXPECT_LT(b_to_a.regions.at({5, y}), 0.3);
  for (int y = 3; y < 5; ++y) EXPECT_NEAR(b_to_a.regions.at({4, y}), 2.0, 0.2);

  MissionSet set;
  set.missions = {room_mission("A", 200, true), room_mission("B", 200, false, 198)};
  const RoomMap a(200, true), b(200, false, 198);
  raycast::ChangeStats stats;
  const MissionPoints got = raycast::detect_changes(set, {&a, &b}, config, 2, &stats);
  EXPECT_EQ(got.sets[0].size(), 40u) << "the box's face";
  EXPECT_EQ(got.sets[1].size(), 0u) << "not B's bent wall";
  EXPECT_EQ(stats.misfit_regions[0], 4u);  // B's bend at x 8-10 m, and A's wall behind it at x 10-12 m
  ASSERT_EQ(stats.warnings.size(), 1u);
  EXPECT_NE(stats.warnings[0].find("in 4 regions of 2 m x 2 m"), std::string::npos) << stats.warnings[0];

  // Judged as before where the regions fit: without the bend, B's wall is
  // not change either, and no warning.
  set.missions[1] = room_mission("B", 200, false);
  const RoomMap straight(200, false);
  raycast::ChangeStats fits;
  EXPECT_EQ(raycast::detect_changes(set, {&a, &straight}, config, 2, &fits).sets[1].size(), 0u);
  EXPECT_TRUE(fits.warnings.empty());
  EXPECT_EQ(fits.misfit_regions[0], 0u);
}

TEST(Misfit, TwoRegionsOffAloneAreJudgedAsConfigured) {
  // B's wall stands two voxels further than A's from y = 6 m on, within two
  // regions (x 10-12 m, y 6-10 m): as likely a thing moved by ten
  // centimetres as a bent map, so it stays change.
  MissionSet set;
  set.missions = {room_mission("A", 200, false), room_mission("B", 200, false, 202)};
  const RoomMap a(200, false), b(200, false, 202);
  raycast::ChangeStats stats;
  const MissionPoints got = raycast::detect_changes(set, {&a, &b}, raycast::VolumetricConfig{}, 2, &stats);
  // A's wall where B saw past it, but its first column, a voxel from
  // where B holds the wall too.
  EXPECT_EQ(got.sets[0].size(), 79u * 60u);
  EXPECT_EQ(stats.misfit_regions[0], 0u);
  EXPECT_TRUE(stats.warnings.empty());
}

TEST(Misfit, RegionsGrowWithTheSiteSoTheirCountStaysBounded) {
  const raycast::VolumetricConfig config;
  // A room 10 m wide: 2 m squares.
  EXPECT_EQ(raycast::region_size(room_mission("A", 200, false), room_mission("B", 200, false), config), 2.0);
  // A yard 100 m across (a point every 0.5 m, each listed 16 times so that
  // every 16th is each of them): 2500 squares of 2 m, 625 of 4 m, 169 of 8 m.
  std::vector<Eigen::Vector3f> points;
  for (int x = 0; x < 200; ++x)
    for (int y = 0; y < 200; ++y)
      for (int k = 0; k < 16; ++k) points.emplace_back(0.5f * float(x) + 0.1f, 0.5f * float(y) + 0.1f, 0.0f);
  const Mission yard = one_scan("A", points);
  EXPECT_EQ(raycast::region_size(yard, yard, config), 8.0);
}
