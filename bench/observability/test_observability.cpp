// The observability of a removed patch: seen empty through it by the other
// mission's scan, not seen behind a wall, and no change where nothing moved.
#include "observability.hpp"

#include <lista/error.hpp>

#include <gtest/gtest.h>

#include <memory>

namespace {

void add_patch(lista::PointSet& p, double x, double half, double step, uint32_t label) {
  for (double y = -half; y <= half + 1e-9; y += step)
    for (double z = -half; z <= half + 1e-9; z += step) {
      p.xyz.emplace_back(float(x), float(y), float(z));
      p.label.push_back(label);
    }
}

// One scan at the origin (true pose identity) holding `points`.
lista::Mission mission_of(const std::string& name, lista::PointSet points) {
  lista::Mission m;
  m.name = name;
  lista::Scan s;
  s.points = std::make_shared<const lista::PointSet>(std::move(points));
  m.scans.push_back(s);
  m.poses_gt.push_back(Eigen::Isometry3d::Identity());
  return m;
}

lista::io::TruthObject object(int id, bool in_b) {
  lista::io::TruthObject o;
  o.id = id;
  o.class_name = "box";
  o.poses["A"] = Eigen::Matrix4d::Identity();
  o.poses["B"] = in_b ? std::optional<Eigen::Matrix4d>(Eigen::Matrix4d::Identity()) : std::nullopt;
  return o;
}

// A: a 20 cm patch 2 m ahead (object 1), a wall 5 m ahead, a patch behind
// the wall (object 3), a patch behind the sensor (object 2, in both). B:
// the wall and object 2: object 1 and 3 were removed.
struct Scene {
  lista::MissionSet set;
  lista::io::GroundTruth truth;
  Scene() {
    lista::PointSet a, b;
    add_patch(a, 2.0, 0.1, 0.02, 1);
    add_patch(a, 7.0, 0.1, 0.02, 3);
    for (lista::PointSet* p : {&a, &b}) {
      add_patch(*p, 5.0, 1.0, 0.02, 0);
      add_patch(*p, -2.0, 0.1, 0.02, 2);
    }
    set.missions = {mission_of("A", a), mission_of("B", b)};
    truth.missions = {"A", "B"};
    truth.objects = {object(1, false), object(2, true), object(3, false)};
  }
};

TEST(Observability, ARemovedPatchIsSeenEmptyAndOneBehindAWallIsNotSeen) {
  Scene scene;
  const auto rows = observability(scene.set, scene.truth, ObservabilityOptions{});
  ASSERT_EQ(rows.size(), 2u);
  const MissionObservability& a = rows[0];
  ASSERT_EQ(a.objects.size(), 2u);  // objects 1 and 3: 2 did not change
  EXPECT_EQ(a.objects[0].id, 1u);
  EXPECT_EQ(a.objects[0].seen_empty, a.objects[0].changed);
  EXPECT_EQ(a.objects[1].id, 3u);
  EXPECT_EQ(a.objects[1].seen_empty, 0u);
  EXPECT_EQ(a.objects[1].seen_present, 0u);
  EXPECT_EQ(a.changed, a.objects[0].changed + a.objects[1].changed);
  EXPECT_EQ(a.in_visible_objects, a.objects[0].changed);
  EXPECT_EQ(rows[1].changed, 0u);  // B holds nothing that changed
}

TEST(Observability, WhatTheOtherMissionStillHoldsIsSomethingThere) {
  Scene scene;
  // Object 1 moved 6 cm sideways in B (a move: over 5 cm): where its patch
  // overlaps the old place, B holds something there.
  scene.truth.objects[0].poses["B"] = Eigen::Matrix4d::Identity();
  (*scene.truth.objects[0].poses["B"])(1, 3) = 0.06;
  lista::PointSet b = *scene.set.missions[1].scans[0].points;
  add_patch(b, 2.0, 0.1, 0.02, 1);
  for (size_t i = b.size() - 121; i < b.size(); ++i) b.xyz[i].y() += 0.06f;
  scene.set.missions[1] = mission_of("B", b);
  const auto rows = observability(scene.set, scene.truth, ObservabilityOptions{});
  const ObjectObservability& moved = rows[0].objects[0];
  EXPECT_EQ(moved.id, 1u);
  EXPECT_GT(moved.seen_present, moved.changed / 2);  // the patch overlaps where it was
  EXPECT_GT(moved.seen_empty, 0u);                   // the strip it left is seen through
}

TEST(Observability, MissionsWithoutTruePosesAreRefused) {
  Scene scene;
  scene.set.missions[1].poses_gt.clear();
  EXPECT_THROW(observability(scene.set, scene.truth, ObservabilityOptions{}), lista::Error);
}

}  // namespace
