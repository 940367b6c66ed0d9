// pair_thresholds: with one scan per mission no voxel can pass the default
// change_threshold (one update per voxel per scan: P 0.7 against 0.4), so
// such a pair takes one hit against one miss as change unless the threshold
// was given; more scans, the default holds.
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

TEST(PairThresholds, OneScanEachTakesOneHitAgainstOneMiss) {
  const raycast::VolumetricConfig c;
  const auto t = raycast::pair_thresholds(missions_of({1, 1, 8}), c);
  ASSERT_EQ(t.value.size(), 2u);
  // A-B: one scan each, the strongest evidence (0.70 against 0.40) passes.
  EXPECT_NEAR(t.value[0], 0.30 - raycast::kStrongestEvidenceSlack, 1e-6);
  EXPECT_GT(0.70 - 0.40, t.value[0]);
  EXPECT_DOUBLE_EQ(t.value[1], c.change_threshold);  // B-C: 8 scans on one side
  ASSERT_EQ(t.notes.size(), 1u);
  EXPECT_TRUE(t.warnings.empty());
  EXPECT_NE(t.notes[0].find("missions 'A' (1 scan) and 'B' (1 scan) are too few scans"), std::string::npos)
      << t.notes[0];
  EXPECT_TRUE(raycast::pair_thresholds(missions_of({2, 2}), c).notes.empty());
}

// A change_threshold the pipeline gave holds for every pair; the pair that
// cannot pass it is warned about, not adapted.
TEST(PairThresholds, AGivenThresholdIsKeptAndWarnedAbout) {
  raycast::VolumetricConfig c;
  c.change_threshold_given = true;
  const auto t = raycast::pair_thresholds(missions_of({1, 1, 8}), c);
  EXPECT_DOUBLE_EQ(t.value[0], c.change_threshold);
  EXPECT_TRUE(t.notes.empty());
  ASSERT_EQ(t.warnings.size(), 1u);
  EXPECT_NE(t.warnings[0].find("differ by at most 0.30, not above change_threshold 0.35"), std::string::npos)
      << t.warnings[0];
  raycast::VolumetricConfig low = c;
  low.change_threshold = 0.25;
  EXPECT_TRUE(raycast::pair_thresholds(missions_of({1, 1}), low).warnings.empty());
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
  EXPECT_TRUE(raycast::pair_thresholds(missions_of({1, 2}), c).notes.empty());  // two hits against one miss: 0.45
}
