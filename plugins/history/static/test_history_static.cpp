// history.static on synthetic missions of one scan each (identity poses, so
// scan points are common-frame points): boxes that move, vanish or stay.
#include <lista_testing/plugin_stage.hpp>
#include "still_history.hpp"

#include <lista/basic_context.hpp>

#include <gtest/gtest.h>

#include <algorithm>

using namespace lista;
using namespace lista::history;

namespace {

constexpr float kStep = 0.04f;

// The surface of an axis-aligned box (no bottom face: it stands on the floor).
void add_box(PointSet& s, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  auto face = [&](int a, int b, int c, float value) {
    for (float u = lo[a]; u <= hi[a] + 1e-4f; u += kStep)
      for (float v = lo[b]; v <= hi[b] + 1e-4f; v += kStep) {
        Eigen::Vector3f p;
        p[a] = u, p[b] = v, p[c] = value;
        s.xyz.push_back(p);
        s.scan.push_back(0);
        s.index.push_back(uint32_t(s.index.size()));
      }
  };
  face(0, 1, 2, hi.z());
  face(1, 2, 0, lo.x()), face(1, 2, 0, hi.x());
  face(0, 2, 1, lo.y()), face(0, 2, 1, hi.y());
}

PointSet box(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  PointSet s;
  add_box(s, lo, hi);
  return s;
}

// A floor around the scene (never part of an object: below every box's top).
void add_floor(PointSet& s) {
  for (float x = -1.f; x <= 6.f; x += kStep)
    for (float y = -1.f; y <= 4.f; y += kStep) {
      s.xyz.emplace_back(x, y, 0.f);
      s.scan.push_back(0);
      s.index.push_back(uint32_t(s.index.size()));
    }
}

void add_mission(MissionSet& set, const std::string& name, std::vector<PointSet> boxes) {
  PointSet cloud;
  add_floor(cloud);
  for (const PointSet& b : boxes)
    for (size_t i = 0; i < b.size(); ++i) {
      cloud.xyz.push_back(b.xyz[i]);
      cloud.scan.push_back(0);
      cloud.index.push_back(uint32_t(cloud.index.size()));
    }
  Mission m;
  m.name = name;
  Scan scan;
  scan.points = std::make_shared<const PointSet>(cloud);
  scan.points_in_file = uint32_t(cloud.size());
  m.scans.push_back(scan);
  set.missions.push_back(m);
}

// An object of `mission` made of the box's points lifted 2 cm off the floor
// (what segmentation keeps of it).
Object object(int id, uint32_t mission, const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  Object o;
  o.id = id;
  o.mission = mission;
  const PointSet all = box(lo, hi);
  for (size_t i = 0; i < all.size(); ++i)
    if (all.xyz[i].z() >= 0.02f) o.points.push_back_from(all, i);
  o.update_geometry();
  return o;
}

ObjectChange change(int id, ChangeStatus status, int match, std::vector<int> history) {
  ObjectChange c;
  c.object_id = id;
  c.status = status;
  c.match = match;
  c.confidence = 0.8;
  c.history = std::move(history);
  if (status == ChangeStatus::moved) {
    c.has_transform = true;
    c.transform(0, 3) = 1.5;
  }
  return c;
}

const Eigen::Vector3f kLo0(0.f, 0.f, 0.f), kHi0(0.6f, 0.4f, 0.8f);  // the box's first place
const Eigen::Vector3f kShift(2.5f, 1.f, 0.f);                          // its second place

struct Scene {
  MissionSet missions;
  ObjectSet objects;
  Matches matches;
};

// A box moved from its first place (mission A) to its second (B), then left
// there in C; the change found it in A and B only.
Scene moved_then_still() {
  Scene s;
  add_mission(s.missions, "A", {box(kLo0, kHi0)});
  add_mission(s.missions, "B", {box(kLo0 + kShift, kHi0 + kShift)});
  add_mission(s.missions, "C", {box(kLo0 + kShift, kHi0 + kShift)});
  s.objects.missions = {"A", "B", "C"};
  s.objects.objects = {object(0, 0, kLo0, kHi0), object(1, 1, kLo0 + kShift, kHi0 + kShift)};
  s.matches.objects = {change(0, ChangeStatus::moved, 1, {0, 1}), change(1, ChangeStatus::moved, 0, {0, 1})};
  return s;
}

}  // namespace

TEST(HistoryStatic, MovedObjectFollowedIntoTheMissionWhereItStoodStill) {
  const Scene s = moved_then_still();
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 2);
  ASSERT_EQ(r.copies, 1u);
  ASSERT_EQ(r.objects.objects.size(), 3u);
  const Object& copy = r.objects.objects[2];
  EXPECT_EQ(copy.id, 2);
  EXPECT_EQ(copy.mission, 2u);
  // Every point of the box in C, nothing of the floor.
  const PointSet there = box(kLo0 + kShift, kHi0 + kShift);
  const auto on_floor = std::count_if(there.xyz.begin(), there.xyz.end(),
                                      [](const Eigen::Vector3f& p) { return p.z() < 0.02f; });
  EXPECT_EQ(copy.points.size(), there.size() - size_t(on_floor));
  EXPECT_GT(copy.bbox_min.z(), 0.01f);
  const ObjectChange* c = r.matches.find(2);
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->status, ChangeStatus::moved);
  EXPECT_EQ(c->match, 0);  // the partner of the object it stood still after
  EXPECT_TRUE(c->has_transform);
  EXPECT_DOUBLE_EQ(c->transform(0, 3), 1.5);
  for (int id : {0, 1, 2}) EXPECT_EQ(r.matches.find(id)->history, (std::vector<int>{0, 1, 2})) << id;
  // The objects that came in are unchanged.
  EXPECT_EQ(r.objects.objects[1].points.size(), s.objects.objects[1].points.size());
  EXPECT_EQ(r.matches.find(1)->match, 0);
}

TEST(HistoryStatic, CopyDoesNotGrowIntoTheWallItStandsAgainst) {
  // The box's second place is 5 cm from a wall that stands in every mission.
  // B's object lacks the face toward the wall (unseen); the copy in C may
  // take wall points near the object's own, but not grow along the wall.
  const Eigen::Vector3f lo = kLo0 + kShift, hi = kHi0 + kShift;
  const float wall_x = hi.x() + 0.05f;
  PointSet wall;
  for (float y = lo.y() - 0.5f; y <= hi.y() + 0.5f; y += kStep)
    for (float z = 0.f; z <= 1.5f; z += kStep) {
      wall.xyz.emplace_back(wall_x, y, z);
      wall.scan.push_back(0);
      wall.index.push_back(uint32_t(wall.index.size()));
    }
  Scene s;
  add_mission(s.missions, "A", {box(kLo0, kHi0), wall});
  add_mission(s.missions, "B", {box(lo, hi), wall});
  add_mission(s.missions, "C", {box(lo, hi), wall});
  s.objects.missions = {"A", "B", "C"};
  Object seen = object(1, 1, lo, hi);
  std::vector<uint32_t> keep;
  for (uint32_t i = 0; i < seen.points.size(); ++i)
    if (seen.points.xyz[i].x() < hi.x() - 1e-3f) keep.push_back(i);
  seen.points = seen.points.select(keep);
  seen.update_geometry();
  s.objects.objects = {object(0, 0, kLo0, kHi0), seen};
  s.matches.objects = {change(0, ChangeStatus::moved, 1, {0, 1}), change(1, ChangeStatus::moved, 0, {0, 1})};
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  ASSERT_EQ(r.copies, 1u);
  const Object& copy = r.objects.objects.back();
  EXPECT_EQ(copy.mission, 2u);
  size_t on_wall = 0, wall_far_from_object = 0;
  for (const Eigen::Vector3f& p : copy.points.xyz)
    if (p.x() > wall_x - 1e-3f) {
      ++on_wall;
      // Over 10 cm from every point of B's object: reached only by growing.
      if (p.y() > lo.y() + 0.12f && p.y() < hi.y() - 0.12f && p.z() < hi.z() - 0.12f) ++wall_far_from_object;
    }
  EXPECT_GT(on_wall, 0u) << "wall points next to the object's own are taken with it";
  EXPECT_EQ(wall_far_from_object, 0u);
  EXPECT_GT(copy.points.size(), seen.points.size() / 2);
}

TEST(HistoryStatic, RemovedObjectFollowedBackIntoEarlierMissions) {
  // Present in A, B and C, gone in D: found in C only (changed against D).
  Scene s;
  for (const char* m : {"A", "B", "C"}) add_mission(s.missions, m, {box(kLo0, kHi0)});
  add_mission(s.missions, "D", {});
  s.objects.missions = {"A", "B", "C", "D"};
  s.objects.objects = {object(7, 2, kLo0, kHi0)};
  s.matches.objects = {change(7, ChangeStatus::removed, -1, {7})};
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  ASSERT_EQ(r.copies, 2u);
  EXPECT_EQ(r.objects.objects[1].mission, 1u);
  EXPECT_EQ(r.objects.objects[2].mission, 0u);
  for (int id : {8, 9}) {
    ASSERT_NE(r.matches.find(id), nullptr);
    EXPECT_EQ(r.matches.find(id)->status, ChangeStatus::removed);
    EXPECT_EQ(r.matches.find(id)->match, -1);
  }
  EXPECT_EQ(r.matches.find(7)->history, (std::vector<int>{9, 8, 7}));  // mission order
}

TEST(HistoryStatic, MoveInTheMiddleIsFollowedBothWaysIntoOneHistory) {
  // Still from A to B, moved from B to C, still from C to D: B's object is
  // followed back into A, C's forward into D, and all four share one history.
  Scene s;
  for (const char* m : {"A", "B"}) add_mission(s.missions, m, {box(kLo0, kHi0)});
  for (const char* m : {"C", "D"}) add_mission(s.missions, m, {box(kLo0 + kShift, kHi0 + kShift)});
  s.objects.missions = {"A", "B", "C", "D"};
  s.objects.objects = {object(0, 1, kLo0, kHi0), object(1, 2, kLo0 + kShift, kHi0 + kShift)};
  s.matches.objects = {change(0, ChangeStatus::moved, 1, {0, 1}), change(1, ChangeStatus::moved, 0, {0, 1})};
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  ASSERT_EQ(r.copies, 2u);
  const Object* in_a = nullptr;
  const Object* in_d = nullptr;
  for (const Object& o : r.objects.objects) {
    if (o.mission == 0) in_a = &o;
    if (o.mission == 3) in_d = &o;
  }
  ASSERT_NE(in_a, nullptr);
  ASSERT_NE(in_d, nullptr);
  const std::vector<int> expected{in_a->id, 0, 1, in_d->id};
  for (const Object& o : r.objects.objects) EXPECT_EQ(r.matches.find(o.id)->history, expected) << "object " << o.id;
  EXPECT_EQ(r.matches.find(in_a->id)->match, 1);  // A's copy stands for B's object: its partner is in C
  EXPECT_EQ(r.matches.find(in_d->id)->match, 0);
}

TEST(HistoryStatic, AddedObjectNotFollowedWhereItChangedAgain) {
  // Added in B, gone again in C: nothing stands still in C.
  Scene s;
  add_mission(s.missions, "A", {});
  add_mission(s.missions, "B", {box(kLo0, kHi0)});
  add_mission(s.missions, "C", {box(kLo0 + kShift, kHi0 + kShift)});
  s.objects.missions = {"A", "B", "C"};
  s.objects.objects = {object(0, 1, kLo0, kHi0)};
  s.matches.objects = {change(0, ChangeStatus::added, -1, {0})};
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  EXPECT_EQ(r.copies, 0u);
  ASSERT_EQ(r.candidates.size(), 1u);
  EXPECT_EQ(r.candidates[0].verdict, "changed");
  EXPECT_LT(r.candidates[0].still_share, 0.1);
}

TEST(HistoryStatic, StaticThingFlaggedByMistakeIsNotCopied) {
  // An 'added' object in B whose box stands in A as well: it did not change,
  // and its shares in A and C are alike, so C gets no copy.
  Scene s;
  for (const char* m : {"A", "B", "C"}) add_mission(s.missions, m, {box(kLo0, kHi0)});
  s.objects.missions = {"A", "B", "C"};
  s.objects.objects = {object(0, 1, kLo0, kHi0)};
  s.matches.objects = {change(0, ChangeStatus::added, -1, {0})};
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  EXPECT_EQ(r.copies, 0u);
  ASSERT_EQ(r.candidates.size(), 1u);
  EXPECT_EQ(r.candidates[0].verdict, "changed");
  EXPECT_GT(r.candidates[0].gone_share, 0.9);
  // Without the comparison it would be copied: the rule is what refuses it.
  StillConfig no_gap;
  no_gap.min_share_gap = 0.0;
  EXPECT_EQ(extend_histories(s.missions, s.objects, s.matches, nullptr, no_gap, 1).copies, 2u);  // C, and A
}

TEST(HistoryStatic, WrongStatusIsCorrectedWhereTheMissionsContradictIt) {
  // New in B and left in C, but reported 'removed' (changed against C):
  // it stands still in C and is gone from A, so it was added. It is copied
  // into C and it and its copy are 'added'.
  Scene s;
  add_mission(s.missions, "A", {});
  for (const char* m : {"B", "C"}) add_mission(s.missions, m, {box(kLo0, kHi0)});
  s.objects.missions = {"A", "B", "C"};
  s.objects.objects = {object(0, 1, kLo0, kHi0)};
  s.matches.objects = {change(0, ChangeStatus::removed, -1, {0})};
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  ASSERT_EQ(r.copies, 1u);
  EXPECT_EQ(r.corrected, (std::vector<int>{0}));
  const Object& copy = r.objects.objects.back();
  EXPECT_EQ(copy.mission, 2u);
  EXPECT_EQ(r.matches.find(copy.id)->status, ChangeStatus::added);
  EXPECT_EQ(r.matches.find(0)->status, ChangeStatus::added);
  EXPECT_EQ(r.matches.find(0)->history, (std::vector<int>{0, copy.id}));
  ASSERT_EQ(r.candidates.size(), 2u);  // A: not there; C: still, and the status with it
  EXPECT_EQ(r.candidates[0].verdict, "changed");
  EXPECT_EQ(r.candidates[1].verdict, "still, added");

  StillConfig off;
  off.follow_contradictions = false;
  const StillResult kept = extend_histories(s.missions, s.objects, s.matches, nullptr, off, 1);
  EXPECT_EQ(kept.copies, 0u);
  EXPECT_TRUE(kept.corrected.empty());
  EXPECT_EQ(kept.matches.find(0)->status, ChangeStatus::removed);
}

TEST(HistoryStatic, StopsWhereTheMissionAlreadyReportsTheObject) {
  Scene s = moved_then_still();
  // C's own change found the box there (whatever it made of it).
  s.objects.objects.push_back(object(5, 2, kLo0 + kShift, kHi0 + kShift));
  s.matches.objects.push_back(change(5, ChangeStatus::removed, -1, {5}));
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  EXPECT_EQ(r.copies, 0u);
  bool reported = false;
  for (const auto& c : r.candidates) reported |= c.source == 1 && c.verdict == "reported";
  EXPECT_TRUE(reported);
}

TEST(HistoryStatic, TwoMissionsAreLeftAsTheyCame) {
  Scene s = moved_then_still();
  s.missions.missions.pop_back();
  s.objects.missions.pop_back();
  const StillResult r = extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1);
  EXPECT_EQ(r.copies, 0u);
  EXPECT_TRUE(r.candidates.empty());
  EXPECT_EQ(r.objects.objects.size(), 2u);
  EXPECT_EQ(r.matches.find(0)->history, (std::vector<int>{0, 1}));
}

TEST(HistoryStatic, MissingMissionIsAnError) {
  Scene s = moved_then_still();
  s.objects.missions[2] = "elsewhere";
  EXPECT_THROW(extend_histories(s.missions, s.objects, s.matches, nullptr, StillConfig{}, 1), Error);
}

TEST(HistoryStatic, StageCarriesGroupsAndRecordsCopies) {
  const Scene s = moved_then_still();
  Groups g;
  g.method = "test";
  g.object_ids = {0, 1};
  g.group = {3, 3};
  g.confidence = {0.9, 0.7};
  g.count = 4;
  auto stage = plugin_test::make_stage("history.static");
  Inputs in;
  in.set("missions", Data::make(s.missions));
  in.set("objects", Data::make(s.objects));
  in.set("matches", Data::make(s.matches));
  in.set("groups", Data::make(g));
  BasicContext ctx("history", 2, 1);
  const Outputs out = stage->run(in, ctx);
  const auto& groups = out.at("groups").as<Groups>();
  EXPECT_EQ(groups.group_of(2), 3);
  EXPECT_EQ(groups.object_ids.size(), groups.confidence.size());
  EXPECT_EQ(out.at("objects").as<ObjectSet>().objects.size(), 3u);
  EXPECT_NE(out.at("matches").as<Matches>().method.find("history.static"), std::string::npos);
  EXPECT_EQ(ctx.info.metrics.at("history").at("copies"), 1.0);
}
