// undetectable_pairs: with one scan per mission no voxel can change at the
// default thresholds (one update per voxel per scan: P 0.7 against 0.4); the
// warning says so and which change_threshold would do; more scans, no warning.
#include <lista_raycast/change_detection.hpp>

#include <gtest/gtest.h>

using namespace lista;

namespace {
MissionSet missions_of(std::vector<size_t> scans) {
  MissionSet set;
  for (size_t m = 0; m < scans.size(); ++m) {
    Mission mission;
    mission.name = std::string(1, char('A' + m));
    mission.scans.resize(scans[m]);
    set.missions.push_back(mission);
  }
  return set;
}
}  // namespace

TEST(UndetectablePairs, OneScanEachCannotPassTheDefaultThreshold) {
  const raycast::VolumetricConfig c;
  const auto w = raycast::undetectable_pairs(missions_of({1, 1, 8}), c);
  ASSERT_EQ(w.size(), 1u);  // A-B only: B-C has 8 scans on one side
  EXPECT_NE(w[0].find("missions 'A' (1 scan) and 'B' (1 scan) can show no change"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("differ by at most 0.30, not above change_threshold 0.35"), std::string::npos) << w[0];
  EXPECT_NE(w[0].find("below 0.30 (e.g. 0.24)"), std::string::npos) << w[0];
  EXPECT_TRUE(raycast::undetectable_pairs(missions_of({2, 2}), c).empty());
  raycast::VolumetricConfig low = c;
  low.change_threshold = 0.25;
  EXPECT_TRUE(raycast::undetectable_pairs(missions_of({1, 1}), low).empty());
}

// What the default change_threshold asks of a voxel (one update per scan):
// three updates in all, at least one in each mission. One hit against one
// miss is not change; one hit against two misses, or two hits against one
// miss, is. The paper's 0.5 asked four to five (one hit against four
// misses, two against two, three against one).
TEST(UndetectablePairs, DefaultThresholdAsksThreeUpdates) {
  const raycast::VolumetricConfig c;
  auto p = [&](int hits, int misses) {
    return raycast::probability(float(hits) * raycast::logodds(c.prob_hit) +
                                float(misses) * raycast::logodds(c.prob_miss));
  };
  auto changed = [&](int hits_here, int misses_there, double threshold) {
    return p(hits_here, 0) - p(0, misses_there) > threshold;
  };
  EXPECT_FALSE(changed(1, 1, c.change_threshold));
  EXPECT_TRUE(changed(1, 2, c.change_threshold));
  EXPECT_TRUE(changed(2, 1, c.change_threshold));
  EXPECT_FALSE(changed(1, 3, 0.5));
  EXPECT_TRUE(changed(1, 4, 0.5));
  EXPECT_EQ(raycast::undetectable_pairs(missions_of({1, 2}), c).size(), 0u);  // two hits against one miss: 0.45
}
