// Dynamic evidence from a mission's other scans: a changed point whose place
// the mission's other scans saw through, after (or before) the scans that saw
// it there, moved during the mission; one that stood still is seen there by
// every scan that looked, or, if open like a wire cart, hit and seen through
// in any order.
#include <lista_raycast/seen_through.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace lista;

namespace {

// A wall at x = 6 and, where `box` is set, a box (x 2.9-3.1, y -0.2-0.2,
// z 0-1.6: a person) in front of it, scanned from `origin` on a grid of
// directions; points in the sensor frame (the sensor does not turn).
struct Hit {
  Eigen::Vector3f point;
  bool on_box;
};
std::vector<Hit> scan_from(const Eigen::Vector3d& origin, bool box) {
  const Eigen::Vector3d lo(2.9, -0.2, 0.0), hi(3.1, 0.2, 1.6);
  std::vector<Hit> hits;
  for (double el = -30.0; el <= 30.0; el += 0.5)
    for (double az = -45.0; az <= 45.0; az += 0.25) {
      const double e = el * M_PI / 180.0, a = az * M_PI / 180.0;
      const Eigen::Vector3d dir(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
      double t = (6.0 - origin.x()) / dir.x();  // the wall
      bool on_box = false;
      if (box) {  // slab test
        double t0 = 0.0, t1 = std::numeric_limits<double>::max();
        for (int k = 0; k < 3; ++k) {
          if (std::abs(dir[k]) < 1e-12) {
            if (origin[k] < lo[k] || origin[k] > hi[k]) t0 = t1 + 1.0;
            continue;
          }
          double a0 = (lo[k] - origin[k]) / dir[k], a1 = (hi[k] - origin[k]) / dir[k];
          if (a0 > a1) std::swap(a0, a1);
          t0 = std::max(t0, a0);
          t1 = std::min(t1, a1);
        }
        if (t0 <= t1 && t0 < t) t = t0, on_box = true;
      }
      hits.push_back({(t * dir).cast<float>(), on_box});
    }
  return hits;
}

// A mission of scans from up to four places, 0.25-1 m apart across the
// box's line of sight, the box there in the scans `box_in`; the changes are the box
// points of the first scan that saw it (common frame), returned with their
// bits. With `stations`, each scan also holds many returns half a metre
// behind its sensor (a wall it stands against), so that its points reach
// less far than the scans stand apart: stations (lista_geometry/stations.hpp).
PointSet judged(const std::vector<bool>& box_in, int threads, bool stations = false) {
  const std::vector<Eigen::Vector3d> origins = {{0.0, 0.0, 0.5}, {0.0, 0.5, 0.5}, {0.0, -0.5, 0.5}, {0.0, 0.25, 0.5}};
  Mission mission;
  mission.name = "A";
  PointSet changed;
  const size_t first = size_t(std::find(box_in.begin(), box_in.end(), true) - box_in.begin());
  for (size_t s = 0; s < box_in.size(); ++s) {
    auto points = std::make_shared<PointSet>();
    const std::vector<Hit> hits = scan_from(origins[s], box_in[s]);
    for (size_t i = 0; i < hits.size(); ++i) {
      points->xyz.push_back(hits[i].point);
      points->scan.push_back(uint32_t(s));
      points->index.push_back(uint32_t(i));
      if (s == first && hits[i].on_box) {
        changed.xyz.push_back(hits[i].point + origins[s].cast<float>());
        changed.scan.push_back(uint32_t(s));
        changed.index.push_back(uint32_t(i));
        changed.changed_against.push_back(changed_against_next);
      }
    }
    for (size_t i = 0; stations && i < 4 * hits.size(); ++i) {
      points->xyz.emplace_back(-0.5f, 0.001f * float(i % 400) - 0.2f, 0.001f * float(i / 400) - 0.2f);
      points->scan.push_back(uint32_t(s));
      points->index.push_back(uint32_t(hits.size() + i));
    }
    Scan scan;
    scan.points = points;
    scan.pose = Eigen::Translation3d(origins[s]) * Eigen::Isometry3d::Identity();
    mission.scans.push_back(scan);
  }
  raycast::mark_seen_through(mission, changed, raycast::VolumetricConfig{}, threads);
  return changed;
}

// How many of the changes got the bit, and (optionally) how many there were.
size_t marked(const std::vector<bool>& box_in, size_t* changes = nullptr) {
  const PointSet set = judged(box_in, 2);
  if (changes) *changes = set.size();
  return set.seen_free_count();
}

}  // namespace

TEST(SeenThrough, AWalkerTheOtherScansSawThroughIsDynamic) {
  size_t changes = 0;
  EXPECT_EQ(marked({true, false, false}, &changes), changes);
  EXPECT_GT(changes, 100u);
  // Seen there by the last scans and through before: arrived during the mission.
  EXPECT_GT(marked({false, false, true}), 0u);
}

TEST(SeenThrough, AThingEveryScanSawThereIsNot) { EXPECT_EQ(marked({true, true, true}), 0u); }

TEST(SeenThrough, SeenThereAgainAfterALookThroughIsNot) {
  // Hit, seen through, hit again: a thing that stood still and that some
  // scans' beams passed (an open frame), or one that came back; no
  // dynamic, though as many scans saw through it as saw it.
  EXPECT_EQ(marked({true, false, false, true}), 0u);
}

TEST(SeenThrough, OneScanMissionsAreLeftAlone) { EXPECT_EQ(marked({true}), 0u); }

TEST(SeenThrough, StationsAreLeftAlone) {
  // The walker's scene again, but each scan's points reach less far than
  // the scans stand apart: a few looks from stations, not a drive.
  const PointSet set = judged({true, false, false}, 2, true);
  EXPECT_GT(set.size(), 100u);
  EXPECT_EQ(set.seen_free_count(), 0u);
}

TEST(SeenThrough, ThePointsAreTheSameForAnyThreadCount) {
  // Votes are kept per scan and counted in scan order after the threads.
  const PointSet one = judged({true, false, false, true}, 1), two = judged({true, false, false, true}, 2);
  EXPECT_EQ(one.changed_against, two.changed_against);
  EXPECT_EQ(judged({true, false, false}, 1).changed_against, judged({true, false, false}, 2).changed_against);
}
