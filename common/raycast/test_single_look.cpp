// One scan per mission: a voxel one scan saw occupied and the other saw free
// is change only where the free look went through the point's surface, i.e.
// the other mission also saw free the space just behind the point along its
// beam (or, where that beam runs into the other mission's floor, level with
// it). A beam that skimmed past a surface it never saw into is no evidence.
#include <lista_raycast/change_detection.hpp>

#include <gtest/gtest.h>

#include <map>
#include <tuple>

using namespace lista;

namespace {

using Key = std::tuple<int, int, int>;

// A map given voxel by voxel; everything else unobserved.
class GivenMap : public raycast::OccupancyMap {
 public:
  std::map<Key, float> cells;
  void set(int x, int y, int z, float l) { cells[{x, y, z}] = l; }
  std::unique_ptr<raycast::OccupancyReader> reader() const override {
    struct Reader : raycast::OccupancyReader {
      const std::map<Key, float>& cells;
      explicit Reader(const std::map<Key, float>& c) : cells(c) {}
      bool logodds(const raycast::Voxel& v, float& out) override {
        auto it = cells.find({v.x(), v.y(), v.z()});
        if (it == cells.end()) return false;
        out = it->second;
        return true;
      }
    };
    return std::make_unique<Reader>(cells);
  }
};

const float hit = raycast::logodds(0.7), miss = raycast::logodds(0.4);

// Mission A: one scan from the origin with one point at `point` (voxels of
// 1 m); mission B: one scan that saw nothing of its own.
MissionSet two_stations(const Eigen::Vector3f& point = {5.5f, 0.5f, 0.5f}) {
  MissionSet set;
  for (const char* name : {"A", "B"}) {
    Mission mission;
    mission.name = name;
    auto pts = std::make_shared<PointSet>();
    if (std::string(name) == "A") {
      pts->xyz.push_back(point);
      pts->scan.push_back(0);
      pts->index.push_back(0);
    }
    Scan scan;
    scan.points = pts;
    mission.scans.push_back(scan);
    set.missions.push_back(mission);
  }
  return set;
}

// A's point is changed against B, given B's map.
bool changed(const GivenMap& b) {
  raycast::VolumetricConfig config;
  config.resolution = 1.0;
  config.neighbourhood = 0;
  GivenMap a;
  a.set(5, 0, 0, hit);
  const MissionPoints got = raycast::detect_changes(two_stations(), {&a, &b}, config, 1);
  return got.sets[0].size() == 1;
}

}  // namespace

TEST(SingleLook, AMissThatWentThroughThePointsSurfaceIsChange) {
  GivenMap b;
  b.set(5, 0, 0, miss);
  b.set(6, 0, 0, miss);  // B saw free where A's surface hid space: the object is gone
  EXPECT_TRUE(changed(b));
}

TEST(SingleLook, AMissThatSkimmedPastTheSurfaceIsNot) {
  GivenMap b;
  b.set(5, 0, 0, miss);  // B's beam crossed the point's voxel ...
  EXPECT_FALSE(changed(b)) << "... but never saw behind it (a box top from afar, a crate's side at a grazing angle)";
  b.set(6, 0, 0, hit);
  b.set(7, 0, 0, hit);
  EXPECT_FALSE(changed(b)) << "behind the point B holds a surface: still no look through it";
}

// A's point is the foot of an object whose beam runs down into the floor;
// behind it B holds the floor, level with it B saw free.
TEST(SingleLook, AtAFootTheSpaceLevelWithThePointIsAsked) {
  raycast::VolumetricConfig config;
  config.resolution = 1.0;
  config.neighbourhood = 0;
  const MissionSet missions = two_stations({3.5f, 0.5f, -2.5f});  // steeply below the sensor
  GivenMap a;
  a.set(3, 0, -3, hit);
  GivenMap b;
  b.set(3, 0, -3, miss);
  b.set(4, 0, -4, hit);  // the floor, where A's beam runs on (depths 1 and 2)
  b.set(5, 0, -4, hit);
  EXPECT_EQ(raycast::detect_changes(missions, {&a, &b}, config, 1).sets[0].size(), 0u);
  b.set(4, 0, -3, miss);  // level with the foot: the object is gone
  EXPECT_EQ(raycast::detect_changes(missions, {&a, &b}, config, 1).sets[0].size(), 1u);
}

// Many scans a mission, not stations (every scan at the origin): the
// default threshold needs more than one look and one hit against one miss
// is no change. A threshold given under prob_hit - prob_miss lets one look
// pass, and then the miss must have gone through the surface too.
TEST(SingleLook, OnlyWhereOneHitAgainstOneMissPasses) {
  raycast::VolumetricConfig config;
  config.resolution = 1.0;
  config.neighbourhood = 0;
  MissionSet many = two_stations();
  for (Mission& m : many.missions) m.scans.resize(5, m.scans[0]);
  GivenMap a;
  a.set(5, 0, 0, hit);
  GivenMap b;
  b.set(5, 0, 0, miss);
  b.set(6, 0, 0, miss);
  EXPECT_EQ(raycast::detect_changes(many, {&a, &b}, config, 1).sets[0].size(), 0u) << "one look among many scans";
  config.change_threshold = 0.24;
  config.change_threshold_given = true;
  EXPECT_EQ(raycast::detect_changes(many, {&a, &b}, config, 1).sets[0].size(), 5u) << "every scan's point";
  b.cells.erase({6, 0, 0});
  EXPECT_EQ(raycast::detect_changes(many, {&a, &b}, config, 1).sets[0].size(), 0u) << "a skimming look";
}

// A mission of stations has most of its points in voxels one scan saw:
// with two scans that each saw their own voxel the share is 1; where both
// scans hit the same voxel it is not one look.
TEST(Stations, OneLookShareCountsPointsWhoseVoxelOneScanSaw) {
  raycast::VolumetricConfig config;
  config.resolution = 1.0;
  MissionSet set = two_stations();
  Mission& a = set.missions[0];
  a.scans.push_back(a.scans[0]);  // a second scan with the same point
  GivenMap once;
  once.set(5, 0, 0, hit);
  EXPECT_DOUBLE_EQ(raycast::one_look_share(a, once, config), 1.0);
  GivenMap twice;
  twice.set(5, 0, 0, 2 * hit);
  EXPECT_DOUBLE_EQ(raycast::one_look_share(a, twice, config), 0.0);
}

// Two missions of stations (several scans each, so the pair keeps the
// default threshold; most points one look): one hit against one miss is
// change when the miss went through the surface; with change_threshold
// given, it is not.
TEST(Stations, OneHitAgainstOneMissIsChangeBetweenStations) {
  raycast::VolumetricConfig config;
  config.resolution = 1.0;
  config.neighbourhood = 0;
  MissionSet set = two_stations();
  // Three stations a mission, 20 m apart: farther apart than their points reach.
  for (Mission& m : set.missions) {
    m.scans.resize(3, m.scans[0]);
    for (size_t i = 0; i < 3; ++i) m.scans[i].pose.translation() = Eigen::Vector3d(20.0 * double(i), 0, 0);
  }
  GivenMap a;
  for (int x : {5, 25, 45}) a.set(x, 0, 0, hit);  // each station's point, one look each
  GivenMap b;
  b.set(5, 0, 0, miss);
  b.set(6, 0, 0, miss);
  // B's stations see their own point 9.5 m out, one look each.
  auto pts = std::make_shared<PointSet>();
  pts->xyz.emplace_back(9.5f, 0.5f, 0.5f);
  pts->scan.push_back(0);
  pts->index.push_back(0);
  for (Scan& s : set.missions[1].scans) s.points = pts;
  for (int x : {9, 29, 49}) b.set(x, 0, 0, hit);
  raycast::ChangeStats stats;
  EXPECT_EQ(raycast::detect_changes(set, {&a, &b}, config, 1, &stats).sets[0].size(), 1u);
  ASSERT_EQ(stats.notes.size(), 1u);
  EXPECT_NE(stats.notes[0].find("scanned from stations"), std::string::npos) << stats.notes[0];
  b.cells.erase({6, 0, 0});
  EXPECT_EQ(raycast::detect_changes(set, {&a, &b}, config, 1).sets[0].size(), 0u) << "a skimming look";
  b.set(6, 0, 0, miss);
  config.change_threshold_given = true;
  EXPECT_EQ(raycast::detect_changes(set, {&a, &b}, config, 1).sets[0].size(), 0u) << "a given threshold holds";
}
