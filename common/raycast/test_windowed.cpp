// detect_changes_windowed: the same changes as building every map first,
// with at most two maps alive at once (five missions here).
#include <lista_raycast/change_detection.hpp>

#include <gtest/gtest.h>

#include <algorithm>

using namespace lista;

namespace {

int live_maps = 0, most_live_maps = 0;

// Mission m's map: a voxel is occupied where (x + m) % 3 == 0, observed
// free elsewhere in x < 20, never observed beyond. Its own scans also saw
// free every voxel of row y = `seen_free_row` (none by default).
class StripeMap : public raycast::OccupancyMap {
 public:
  explicit StripeMap(int m, int seen_free_row = -1) : m_(m), seen_free_row_(seen_free_row) {
    most_live_maps = std::max(most_live_maps, ++live_maps);
  }
  ~StripeMap() override { --live_maps; }
  std::unique_ptr<raycast::OccupancyReader> reader() const override {
    struct Reader : raycast::OccupancyReader {
      int m, row;
      Reader(int mission, int seen_free_row) : m(mission), row(seen_free_row) {}
      bool logodds(const raycast::Voxel& v, float& out) override {
        if (v.x() >= 20) return false;
        out = ((v.x() + m) % 3 + 3) % 3 == 0 ? 3.0f : -2.0f;
        return true;
      }
      bool seen_free(const raycast::Voxel& v) override { return v.y() == row; }
    };
    return std::make_unique<Reader>(m_, seen_free_row_);
  }

 private:
  int m_, seen_free_row_;
};

// Five StripeMaps, and the views detect_changes takes.
struct StripeMaps {
  std::vector<std::unique_ptr<raycast::OccupancyMap>> maps;
  std::vector<const raycast::OccupancyMap*> views;
  explicit StripeMaps(int seen_free_row = -1) {
    for (int m = 0; m < 5; ++m) {
      maps.push_back(std::make_unique<StripeMap>(m, seen_free_row));
      views.push_back(maps.back().get());
    }
  }
};

// Voxels of 1 m, the point's own voxel only.
raycast::VolumetricConfig unit_voxels() {
  raycast::VolumetricConfig config;
  config.resolution = 1.0;
  config.neighbourhood = 0;
  return config;
}

MissionSet five_missions() {
  MissionSet set;
  for (int m = 0; m < 5; ++m) {
    Mission mission;
    mission.name = std::string(1, char('A' + m));
    for (int s = 0; s < 2; ++s) {
      auto pts = std::make_shared<PointSet>();
      for (int x = 0; x < 24; ++x) {
        pts->xyz.emplace_back(float(x) + 0.5f, 0.5f + float(s), 0.5f);
        pts->scan.push_back(uint32_t(s));
        pts->index.push_back(uint32_t(x));
      }
      Scan scan;
      scan.points = pts;
      mission.scans.push_back(scan);
    }
    set.missions.push_back(mission);
  }
  return set;
}

}  // namespace

TEST(DetectChangesWindowed, SameChangesWithAtMostTwoMapsAlive) {
  const MissionSet missions = five_missions();
  const raycast::VolumetricConfig config = unit_voxels();

  auto all = std::make_unique<StripeMaps>();
  raycast::ChangeStats stats_all;
  const MissionPoints expected = raycast::detect_changes(missions, all->views, config, 2, &stats_all);
  all.reset();
  ASSERT_EQ(live_maps, 0);

  most_live_maps = 0;
  std::vector<size_t> built;
  raycast::ChangeStats stats_windowed;
  const MissionPoints got = raycast::detect_changes_windowed(
      missions,
      [&](size_t m) {
        built.push_back(m);
        return std::make_unique<StripeMap>(int(m));
      },
      config, 2, &stats_windowed);
  EXPECT_EQ(live_maps, 0) << "every map freed at the end";
  EXPECT_EQ(most_live_maps, 2);
  EXPECT_EQ(built, (std::vector<size_t>{0, 1, 2, 3, 4})) << "each map built once, in mission order";
  ASSERT_EQ(got.sets.size(), expected.sets.size());
  EXPECT_EQ(got.missions, expected.missions);
  for (size_t m = 0; m < got.sets.size(); ++m) {
    EXPECT_GT(got.sets[m].size(), 0u) << "the stripes move by one voxel per mission: every mission changes";
    EXPECT_EQ(got.sets[m].xyz, expected.sets[m].xyz);
    EXPECT_EQ(got.sets[m].changed_against, expected.sets[m].changed_against);
    EXPECT_EQ(got.sets[m].index, expected.sets[m].index);
  }
  EXPECT_EQ(stats_windowed.changed_points, stats_all.changed_points);
  EXPECT_EQ(stats_windowed.changed_voxels, stats_all.changed_voxels);
}

// Scan 1's points lie in row y = 1, which the missions' own scans also saw free.
TEST(DetectChanges, ChangedPointsTheirOwnMissionSawFreeCarryTheDynamicBit) {
  const StripeMaps maps(1);
  raycast::ChangeStats stats;
  const MissionPoints got = raycast::detect_changes(five_missions(), maps.views, unit_voxels(), 2, &stats);
  for (size_t m = 0; m < got.sets.size(); ++m) {
    const PointSet& set = got.sets[m];
    size_t flagged = 0;
    for (size_t i = 0; i < set.size(); ++i) {
      const bool dynamic = set.changed_against[i] & seen_free_in_own_mission;
      EXPECT_EQ(dynamic, set.scan[i] == 1) << "mission " << m << " point " << i;
      EXPECT_NE(set.changed_against[i] & changed_against_either, 0) << "still a change point with its neighbours";
      flagged += dynamic;
    }
    EXPECT_GT(flagged, 0u);
    EXPECT_EQ(stats.seen_free_points[m], flagged);
    EXPECT_EQ(set.seen_free_count(), flagged);
    EXPECT_EQ(set.changed_against_all() & seen_free_in_own_mission, 0) << "changed_against_all names neighbours only";
  }
}
