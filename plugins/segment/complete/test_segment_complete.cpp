// segment.complete on a synthetic two-mission scene: a floor, a box moved by
// less than its size (only slivers detected), a static box nearby.
#include <lista_testing/point_scenes.hpp>
#include "completion.hpp"

#include <lista_geometry/object_geometry.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <set>

using namespace lista;
using test_support::add_box_surface;

namespace {

constexpr float kStep = 0.04f;

// Appends a mission of one scan holding `cloud`.
void add_mission(MissionSet& set, const std::string& name, const PointSet& cloud) {
  Mission mission;
  mission.name = name;
  Scan scan;
  scan.points = std::make_shared<const PointSet>(cloud);
  scan.points_in_file = uint32_t(cloud.size());
  mission.scans.push_back(scan);
  set.missions.push_back(mission);
}

struct Scene {
  MissionSet missions;
  PointSet cloud[2];
};

// A flat floor at z = 0 over [x0, x1] x [y0, y1], points kStep apart.
void add_floor(PointSet& c, float x0, float x1, float y0, float y1) {
  for (float x = x0; x <= x1; x += kStep)
    for (float y = y0; y <= y1; y += kStep) {
      c.xyz.emplace_back(x, y, 0.f);
      c.scan.push_back(0);
      c.index.push_back(uint32_t(c.index.size()));
    }
}

// Floor z = 0 over [-1, 4] x [-1, 3]; the moved box [x0, x0 + 0.6] x [0, 0.4]
// x [0, 0.8] (A: x0 = 1.0, B: x0 = 1.3); a static box [2.5, 3.0] x [0, 0.5] x
// [0, 0.6] in both missions (0.6 m from the moved box in B).
// `removed_at` (x, y of its low corner; none if NaN): a box of the moved box's
// size in A only.
Scene make_scene(float static_x = 2.5f, float static_h = 0.6f,
                 Eigen::Vector2f removed_at = Eigen::Vector2f::Constant(std::nanf(""))) {
  Scene s;
  for (int m = 0; m < 2; ++m) {
    PointSet& c = s.cloud[m];
    add_floor(c, -1.f, 4.f, -1.f, 3.f);
    const float x0 = m == 0 ? 1.0f : 1.3f;
    add_box_surface(c, {x0, 0.f, 0.f}, {x0 + 0.6f, 0.4f, 0.8f}, kStep);
    add_box_surface(c, {static_x, 0.f, 0.f}, {static_x + 0.5f, 0.5f, static_h}, kStep);
    if (m == 0 && !removed_at.hasNaN())
      add_box_surface(c, {removed_at.x(), removed_at.y(), 0.f}, {removed_at.x() + 0.6f, removed_at.y() + 0.4f, 0.8f},
                      kStep);
    for (size_t i = 0; i < c.size(); ++i) c.index[i] = uint32_t(i);
    add_mission(s.missions, m == 0 ? "A" : "B", c);
  }
  return s;
}

// An object of `mission` holding the points of `c` that `keep` accepts.
template <class Keep>
Object object_where(const PointSet& c, uint32_t mission, Keep keep) {
  Object o;
  o.mission = mission;
  for (size_t i = 0; i < c.size(); ++i)
    if (keep(c.xyz[i])) o.points.push_back_from(c, i);
  o.update_geometry();
  return o;
}

Object sliver(const PointSet& c, uint32_t mission, float x_lo, float x_hi) {
  return object_where(c, mission, [&](const Eigen::Vector3f& p) {
    return p.x() >= x_lo && p.x() < x_hi && p.y() <= 0.41f && p.z() > 0.05f && p.z() < 0.81f;
  });
}

// The same, as the only object (id 0) of a set over missions A and B.
template <class Keep>
ObjectSet one_object(const PointSet& c, uint32_t mission, Keep keep) {
  ObjectSet in;
  in.missions = {"A", "B"};
  in.objects.push_back(object_where(c, mission, keep));
  in.objects.back().id = 0;
  return in;
}

size_t count_in_box(const PointSet& s, Eigen::Vector3f lo, Eigen::Vector3f hi) {
  size_t n = 0;
  for (const auto& p : s.xyz) n += (p.array() >= lo.array() - 1e-4f).all() && (p.array() <= hi.array() + 1e-4f).all();
  return n;
}

// B's moved box, whole (as segment.carve leaves it), above the floor clearance.
Object moved_box_in_b(const Scene& s) {
  return object_where(s.cloud[1], 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 1.29f && p.x() <= 1.91f && p.y() <= 0.41f && p.z() > 0.05f;
  });
}

// Objects of missions A and B, numbered in order.
ObjectSet object_set(std::vector<Object> objects) {
  ObjectSet in;
  in.missions = {"A", "B"};
  in.objects = std::move(objects);
  for (size_t i = 0; i < in.objects.size(); ++i) in.objects[i].id = int(i);
  return in;
}

// Pair completion alone: no self-completion, no nested fragments.
segment::CompletionConfig pairs_only() {
  segment::CompletionConfig c;
  c.self_complete = false;
  c.nested_share = 0.0;
  return c;
}

ObjectSet slivers(const Scene& s) {
  ObjectSet in;
  in.missions = {"A", "B"};
  in.objects.push_back(sliver(s.cloud[0], 0, 0.99f, 1.29f));  // A: where B's box is not
  in.objects.push_back(sliver(s.cloud[1], 1, 1.61f, 1.91f));  // B: where A's box was not
  in.objects[0].id = 0;
  in.objects[1].id = 1;
  return in;
}

}  // namespace

TEST(SegmentComplete, ShortMoveSliversGrowIntoWholeBoxes) {
  const Scene s = make_scene();
  const ObjectSet in = slivers(s);
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, {}, &st);
  ASSERT_EQ(out.objects.size(), 2u);
  EXPECT_EQ(st.completed, 1u);
  ASSERT_EQ(st.pair_notes.size(), 1u);  // what -v prints
  EXPECT_EQ(st.pair_notes[0].rfind("objects 0 + 1: completed, ", 0), 0u) << st.pair_notes[0];
  const float clear = 0.08f;
  // Every box point above the floor clearance is now in the object, nothing else.
  const size_t box_a = count_in_box(s.cloud[0], {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f});
  const size_t box_b = count_in_box(s.cloud[1], {1.3f, 0.f, clear}, {1.9f, 0.4f, 0.8f});
  EXPECT_GT(out.objects[0].points.size(), in.objects[0].points.size() * 3 / 2);
  EXPECT_EQ(count_in_box(out.objects[0].points, {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f}), box_a);
  EXPECT_EQ(count_in_box(out.objects[1].points, {1.3f, 0.f, clear}, {1.9f, 0.4f, 0.8f}), box_b);
  for (const auto& o : out.objects) {
    EXPECT_EQ(count_in_box(o.points, {-1.f, -1.f, -0.01f}, {4.f, 3.f, 0.01f}), 0u) << "floor points added";
    EXPECT_EQ(count_in_box(o.points, {2.5f, 0.f, 0.f}, {3.0f, 0.5f, 0.6f}), 0u) << "static box swallowed";
  }
  // No point twice.
  for (const auto& o : out.objects) {
    std::set<uint32_t> idx(o.points.index.begin(), o.points.index.end());
    EXPECT_EQ(idx.size(), o.points.size());
  }
  EXPECT_EQ(out.objects[0].id, 0);
  EXPECT_EQ(out.objects[1].id, 1);
}

TEST(SegmentComplete, AShortMoveAgainstAWallGrowsInsideThePairsOwnBox) {
  // A wall 5 cm behind the moved box (y = -0.05, in both missions): the
  // pair's region (+ box_margin) takes it in, and the growth climbs it
  // (to the region's edge: leaks counted there, judged at max_leak 0.02).
  Scene s = make_scene();
  const ObjectSet in = slivers(s);
  for (int m = 0; m < 2; ++m) {
    PointSet& c = s.cloud[m];
    for (float x = -1.f; x <= 4.f; x += kStep)
      for (float z = kStep; z <= 2.5f; z += kStep) {
        c.xyz.emplace_back(x, -0.05f, z);
        c.scan.push_back(0);
        c.index.push_back(uint32_t(c.index.size()));
      }
    s.missions.missions[m].scans[0].points = std::make_shared<const PointSet>(c);
  }
  segment::CompletionConfig c;
  c.self_complete = false;
  c.max_leak = 0.02;
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  EXPECT_EQ(st.completed, 1u);
  ASSERT_EQ(st.pair_notes.size(), 1u);
  EXPECT_NE(st.pair_notes[0].find("completed inside the pair's own box"), std::string::npos) << st.pair_notes[0];
  // The union of the slivers' boxes spans x 0.99..1.91: all of A's box but
  // its far face is in it, nothing of the wall.
  const Eigen::Vector3f wall_lo{-1.f, -0.06f, 0.f}, wall_hi{4.f, -0.04f, 2.5f};
  for (const auto& o : out.objects) EXPECT_EQ(count_in_box(o.points, wall_lo, wall_hi), 0u) << "wall added";
  const Eigen::Vector3f middle_lo{1.3f, 0.f, 0.1f}, middle_hi{1.6f, 0.4f, 0.8f};  // A's box where B's overlaps it
  EXPECT_EQ(count_in_box(out.objects[0].points, middle_lo, middle_hi), count_in_box(s.cloud[0], middle_lo, middle_hi));

  // leak_growth = base: the pair is left as two slivers.
  c.leak_growth = segment::LeakGrowth::base;
  segment::CompletionStats st_base;
  const ObjectSet out_base = segment::complete_objects(in, s.missions, c, &st_base);
  EXPECT_EQ(st_base.completed, 0u);
  ASSERT_EQ(st_base.pair_notes.size(), 1u);
  EXPECT_NE(st_base.pair_notes[0].find("not completed, a growth leaks out"), std::string::npos) << st_base.pair_notes[0];
  EXPECT_EQ(out_base.objects[0].points.size(), in.objects[0].points.size());
}

// The points a completion adds are the mission's, not change points: they
// take the object's ChangedAgainst bits, so matching still knows against
// which mission each grown object changed.
TEST(SegmentComplete, GrownPointsKeepTheObjectsChangedAgainstBits) {
  const Scene s = make_scene();
  ObjectSet in = slivers(s);
  in.objects[0].points.changed_against.assign(in.objects[0].points.size(), changed_against_next);
  in.objects[1].points.changed_against.assign(in.objects[1].points.size(), changed_against_previous);
  const ObjectSet out = segment::complete_objects(in, s.missions, {}, nullptr);
  ASSERT_EQ(out.objects.size(), 2u);
  for (size_t k = 0; k < 2; ++k) {
    const PointSet& p = out.objects[k].points;
    EXPECT_GT(p.size(), in.objects[k].points.size());
    p.check_consistent();
    ASSERT_EQ(p.changed_against.size(), p.size());
    EXPECT_EQ(p.changed_against_all(), k == 0 ? changed_against_next : changed_against_previous);
  }
}

TEST(SegmentComplete, DisagreeingShapesAreLeftAlone) {
  // A's sliver of the moved box paired with a sliver of a tall static cabinet
  // in B: no rigid object has both grown shapes, so nothing changes.
  const Scene s = make_scene(2.5f, 1.6f);
  ObjectSet in = slivers(s);
  in.objects[1] = sliver(s.cloud[1], 1, 2.49f, 2.7f);
  in.objects[1].id = 1;
  segment::CompletionConfig c;
  c.pair_gap = 2.0;
  c.self_complete = false;
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  EXPECT_EQ(st.pairs, 1u);
  EXPECT_EQ(st.rejected, 1u);
  ASSERT_EQ(st.pair_notes.size(), 1u);
  // The cabinet's growth leaks out of the pair's region; kept to the pair's
  // own box, the two shapes still differ.
  EXPECT_NE(st.pair_notes[0].find("not completed, grown shapes differ inside the pair's own box"), std::string::npos)
      << st.pair_notes[0];
  EXPECT_EQ(out.objects[0].points.size(), in.objects[0].points.size());
  EXPECT_EQ(out.objects[1].points.size(), in.objects[1].points.size());
}

// A static low cabinet with a back panel stands in both missions, x in
// [1.0, 1.6]; a box touching its left end was taken away (A) and a post
// put down touching its right end (B). Both growths reach the cabinet, and
// box + cabinet has the size of post + cabinet, as if one object had moved
// 0.3 m. Registered, the two grown objects fit better where they stand than
// at any pose a move would give: the pair is refused, the cabinet stays out.
TEST(SegmentComplete, AStaticThingBetweenTwoChangesIsNotGrownInto) {
  Scene s;
  for (int m = 0; m < 2; ++m) {
    PointSet& c = s.cloud[m];
    add_floor(c, -1.f, 3.f, -1.f, 2.f);
    add_box_surface(c, {1.0f, 0.f, 0.f}, {1.6f, 0.5f, 0.4f}, kStep);
    add_box_surface(c, {1.0f, 0.44f, 0.4f}, {1.6f, 0.5f, 0.7f}, kStep);
    if (m == 0) add_box_surface(c, {0.72f, 0.1f, 0.f}, {0.98f, 0.4f, 0.6f}, kStep);
    if (m == 1) add_box_surface(c, {1.62f, 0.2f, 0.f}, {1.76f, 0.34f, 0.7f}, kStep);
    for (size_t i = 0; i < c.size(); ++i) c.index[i] = uint32_t(i);
    add_mission(s.missions, m == 0 ? "A" : "B", c);
  }
  auto small_box = [&](int m, float x_lo, float x_hi) {
    return object_where(s.cloud[m], uint32_t(m), [&](const Eigen::Vector3f& p) {
      return p.x() >= x_lo && p.x() <= x_hi && p.y() >= 0.09f && p.y() <= 0.41f && p.z() > 0.05f;
    });
  };
  const ObjectSet in = object_set({small_box(0, 0.71f, 0.99f), small_box(1, 1.61f, 1.77f)});
  segment::CompletionConfig c = pairs_only();
  c.pair_gap = 1.5;
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  ASSERT_EQ(st.pair_notes.size(), 1u);
  EXPECT_NE(st.pair_notes[0].find("not completed, the grown objects fit best where they stand"), std::string::npos)
      << st.pair_notes[0];
  for (const auto& o : out.objects)
    EXPECT_EQ(count_in_box(o.points, {1.01f, 0.01f, 0.1f}, {1.59f, 0.49f, 0.79f}), 0u) << "the cabinet was taken";
  // Without the check the sizes agree and the cabinet is taken on both sides.
  c.still_check = false;
  segment::CompletionStats st_off;
  segment::complete_objects(in, s.missions, c, &st_off);
  EXPECT_EQ(st_off.completed, 1u) << (st_off.pair_notes.empty() ? "" : st_off.pair_notes[0]);
}

// A tall static cabinet stands 0.2 m from A's sliver of the moved box, and
// the difference flagged a sliver of it in B (residual misalignment): that is
// A's nearest candidate (0.2 m against the true partner's 0.32 m). Its shapes
// disagree, so with pair_retry A's sliver goes on to its next candidate.
TEST(SegmentComplete, ARefusedPairFreesItsObjectsForTheirNextCandidates) {
  const Scene s = make_scene(0.3f, 1.6f);  // static cabinet x 0.3..0.8, 1.6 m tall
  ObjectSet in = slivers(s);
  in.objects.push_back(object_where(s.cloud[1], 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 0.59f && p.x() <= 0.81f && p.z() > 0.05f;  // its whole height
  }));
  in.objects.back().id = 2;
  segment::CompletionConfig c;
  c.self_complete = false;
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  ASSERT_EQ(st.pair_notes.size(), 2u) << st.pair_notes[0];
  EXPECT_EQ(st.pair_notes[0].rfind("objects 0 + 2: not completed, grown shapes differ", 0), 0u) << st.pair_notes[0];
  EXPECT_EQ(st.pair_notes[1].rfind("objects 0 + 1: completed", 0), 0u) << st.pair_notes[1];
  EXPECT_EQ(st.pairs, 2u);
  EXPECT_EQ(st.completed, 1u);
  const float clear = 0.08f;
  EXPECT_EQ(count_in_box(out.objects[0].points, {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f}),
            count_in_box(s.cloud[0], {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f}));
  EXPECT_EQ(out.objects[2].points.size(), in.objects[2].points.size());

  // Without: A's sliver is offered the cabinet only, and stays a sliver.
  c.pair_retry = false;
  segment::CompletionStats st_once;
  const ObjectSet out_once = segment::complete_objects(in, s.missions, c, &st_once);
  EXPECT_EQ(st_once.pairs, 1u);
  EXPECT_EQ(st_once.completed, 0u);
  EXPECT_EQ(out_once.objects[0].points.size(), in.objects[0].points.size());
}

// After a cut (segment.carve), B holds the moved box whole; A holds its
// sliver and, beside it, an identical box that was removed, whose box also
// overlaps B's. Both candidates touch (gaps under one voxel). The removed
// box and the moved one have one shape, so that pair would complete (adding
// nothing) and take B's box from the sliver: the nearer centroids go first.
TEST(SegmentComplete, AmongOverlappingBoxesTheNearerCentroidsPairFirst) {
  const Scene s = make_scene(3.2f, 0.6f, {1.85f, 0.35f});  // removed box x 1.85..2.45, y 0.35..0.75
  const Object removed = object_where(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
    return p.x() >= 1.84f && p.y() >= 0.34f && p.x() <= 2.46f && p.z() > 0.05f;  // the removed box, whole
  });
  const ObjectSet in = object_set({removed, sliver(s.cloud[0], 0, 0.99f, 1.29f), moved_box_in_b(s)});
  segment::CompletionConfig c = pairs_only();
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  ASSERT_FALSE(st.pair_notes.empty());
  EXPECT_EQ(st.pair_notes[0].rfind("objects 1 + 2: completed", 0), 0u) << st.pair_notes[0];
  EXPECT_EQ(st.completed, 1u);
  const float clear = 0.08f;
  EXPECT_EQ(count_in_box(out.objects[1].points, {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f}),
            count_in_box(s.cloud[0], {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f}));

  // In id order the removed box pairs first and the sliver stays a sliver.
  c.pair_order = segment::PairOrder::gap;
  segment::CompletionStats st_id;
  const ObjectSet out_id = segment::complete_objects(in, s.missions, c, &st_id);
  ASSERT_FALSE(st_id.pair_notes.empty());
  EXPECT_EQ(st_id.pair_notes[0].rfind("objects 0 + 2: completed", 0), 0u) << st_id.pair_notes[0];
  EXPECT_EQ(out_id.objects[1].points.size(), in.objects[1].points.size());
}

// A short move with a turn leaves slivers at both ends of the object: A
// holds its box as two end strips (two objects), B the moved box whole. The
// nearer strip's growth reaches the other strip, which is joined: A's object
// is whole and one.
TEST(SegmentComplete, APairsGrowthJoinsTheFragmentsItReaches) {
  const Scene s = make_scene(3.2f);
  const ObjectSet in =
      object_set({sliver(s.cloud[0], 0, 0.99f, 1.15f), sliver(s.cloud[0], 0, 1.45f, 1.61f), moved_box_in_b(s)});
  segment::CompletionConfig c = pairs_only();
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  ASSERT_EQ(out.objects.size(), 2u);
  EXPECT_EQ(st.joined, 1u);
  ASSERT_FALSE(st.pair_notes.empty());
  EXPECT_EQ(st.pair_notes[0].rfind("objects 1 + 2: completed (joined: 0 to 1)", 0), 0u) << st.pair_notes[0];
  EXPECT_EQ(out.objects[0].id, 0);  // renumbered
  EXPECT_EQ(out.objects[1].id, 1);
  const float clear = 0.08f;
  EXPECT_EQ(count_in_box(out.objects[0].points, {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f}),
            count_in_box(s.cloud[0], {1.0f, 0.f, clear}, {1.6f, 0.4f, 0.8f}));
  std::set<uint32_t> idx(out.objects[0].points.index.begin(), out.objects[0].points.index.end());
  EXPECT_EQ(idx.size(), out.objects[0].points.size()) << "a point twice";

  // Without: the pair completes on the nearer strip alone, the other stays.
  c.join_fragments = false;
  segment::CompletionStats st_alone;
  const ObjectSet alone = segment::complete_objects(in, s.missions, c, &st_alone);
  EXPECT_EQ(alone.objects.size(), 3u);
  EXPECT_EQ(st_alone.joined, 0u);
}

// A fragment of another object is joined only where the shapes then agree:
// a box removed from beside A's pose is reached by the sliver's growth, but
// joined it makes A's object twice as long as B's.
TEST(SegmentComplete, AFragmentThatSpoilsTheShapeIsNotJoined) {
  const Scene s = make_scene(3.2f, 0.6f, {1.65f, 0.f});  // removed box x 1.65..2.25, in A only
  const Object removed = object_where(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
    return p.x() >= 1.64f && p.x() <= 2.26f && p.y() <= 0.41f && p.z() > 0.05f;
  });
  const ObjectSet in = object_set({sliver(s.cloud[0], 0, 1.45f, 1.61f), removed, moved_box_in_b(s)});
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, pairs_only(), &st);
  EXPECT_EQ(st.joined, 0u);
  ASSERT_EQ(out.objects.size(), 3u);
  EXPECT_EQ(out.objects[1].points.size(), in.objects[1].points.size());
  ASSERT_GE(st.pair_notes.size(), 2u);
  EXPECT_EQ(st.pair_notes[0].rfind("objects 0 + 2: not joined with 1, joined shapes differ", 0), 0u) << st.pair_notes[0];
  EXPECT_EQ(st.pair_notes[1].rfind("objects 0 + 2: completed inside", 0), 0u) << st.pair_notes[1];
}

// The default pipeline runs the stage again after segment.carve: what the
// first pass made whole comes through the second unchanged, its floor
// included (a remeasured floor may differ by microns).
TEST(SegmentComplete, ASecondPassLeavesWholeObjectsAsTheyCame) {
  const Scene s = make_scene();
  ObjectSet once = segment::complete_objects(slivers(s), s.missions, {});
  ASSERT_TRUE(std::isfinite(once.objects[0].floor_z));
  once.objects[0].floor_z += 0.004f;  // as if measured on other points: kept, not remeasured
  const ObjectSet twice = segment::complete_objects(once, s.missions, {});
  ASSERT_EQ(twice.objects.size(), once.objects.size());
  for (size_t i = 0; i < once.objects.size(); ++i) {
    EXPECT_EQ(twice.objects[i].points.size(), once.objects[i].points.size());
    EXPECT_EQ(twice.objects[i].floor_z, once.objects[i].floor_z);
  }
}

TEST(SegmentComplete, FarApartClustersAreNotPaired) {
  const Scene s = make_scene();
  ObjectSet in = slivers(s);
  segment::CompletionConfig c;
  c.pair_gap = 0.1;  // the slivers are 0.32 m apart
  c.self_complete = false;
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  EXPECT_EQ(st.pairs, 0u);
  EXPECT_EQ(out.objects[0].points.size(), in.objects[0].points.size());
}

TEST(SegmentComplete, UnknownMissionIsAClearError) {
  const Scene s = make_scene();
  ObjectSet in = slivers(s);
  in.missions = {"A", "C"};
  try {
    segment::complete_objects(in, s.missions, {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'C'"), std::string::npos) << e.what();
  }
}

TEST(SegmentComplete, StageRunsThroughItsManifest) {
  const Scene s = make_scene();
  EXPECT_EQ(plugin_test::stage_info("segment.complete").inputs.size(), 2u);
  auto stage = plugin_test::make_stage("segment.complete");
  Inputs in;
  in.set("objects", Data::make(slivers(s)));
  in.set("missions", Data::make(s.missions));
  BasicContext ctx("complete", 2, 1);
  const auto out = stage->run(in, ctx);
  const auto& objects = out.at("objects").as<ObjectSet>();
  EXPECT_GT(objects.objects[0].points.size(), slivers(s).objects[0].points.size());
}

TEST(SegmentComplete, ObjectsGetTheirBaseBackButNotTheFloor) {
  // The difference found the moved box only above 12 cm (as next to a floor
  // it cannot confirm change); self-completion gives the rest back.
  const Scene s = make_scene();
  const ObjectSet in = one_object(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
    return p.x() >= 0.99f && p.x() <= 1.61f && p.y() <= 0.41f && p.z() > 0.12f;
  });
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, {}, &st);
  EXPECT_EQ(st.self_completed, 1u);
  ASSERT_EQ(st.object_notes.size(), 1u);  // what -v prints
  EXPECT_EQ(st.object_notes[0].rfind("object 0: grown inside its box, ", 0), 0u) << st.object_notes[0];
  const auto& got = out.objects[0].points;
  EXPECT_GT(count_in_box(got, {1.0f, 0.f, 0.03f}, {1.6f, 0.4f, 0.12f}), 0u);
  EXPECT_EQ(count_in_box(got, {1.0f, 0.f, 0.03f}, {1.6f, 0.4f, 0.8f}),
            count_in_box(s.cloud[0], {1.0f, 0.f, 0.03f}, {1.6f, 0.4f, 0.8f}));
  EXPECT_EQ(count_in_box(got, {-1.f, -1.f, -0.01f}, {4.f, 3.f, 0.01f}), 0u) << "floor points added";
}

TEST(SegmentComplete, AgainstAWallOnlyTheObjectsOwnBoxIsAdded) {
  // The box stands against a wall (x = 0.95, floor to 2.5 m): growing inside
  // the box grown by box_margin would leak up the wall. The difference found
  // its top and its far face (x = 1.6) only, as a sparse scan's may.
  Scene s = make_scene();
  PointSet& c = s.cloud[0];
  for (float y = -1.f; y <= 3.f; y += kStep)
    for (float z = kStep; z <= 2.5f; z += kStep) {
      c.xyz.emplace_back(0.95f, y, z);
      c.scan.push_back(0);
      c.index.push_back(uint32_t(c.index.size()));
    }
  s.missions.missions[0].scans[0].points = std::make_shared<const PointSet>(c);
  const ObjectSet in = one_object(c, 0, [](const Eigen::Vector3f& p) {
    const bool in_box = p.x() >= 0.99f && p.x() <= 1.61f && p.y() <= 0.41f && p.z() < 0.81f;
    return in_box && (p.z() > 0.6f || (p.x() > 1.55f && p.z() > 0.12f));
  });
  const Eigen::Vector3f near_face_lo{0.99f, 0.f, 0.2f}, near_face_hi{1.05f, 0.4f, 0.5f};
  ASSERT_GT(count_in_box(c, near_face_lo, near_face_hi), 0u);
  const Eigen::Vector3f wall_lo{0.94f, -1.f, 0.25f}, wall_hi{0.96f, 3.f, 2.5f};

  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, {}, &st);
  ASSERT_EQ(st.object_notes.size(), 1u);  // what -v prints
  EXPECT_NE(st.object_notes[0].find("leaks out of its box"), std::string::npos) << st.object_notes[0];
  EXPECT_NE(st.object_notes[0].find("grown inside its own box and base"), std::string::npos) << st.object_notes[0];
  const auto& got = out.objects[0].points;
  EXPECT_GT(count_in_box(got, {1.0f, 0.f, 0.03f}, {1.6f, 0.4f, 0.12f}), 0u) << "base not added";
  EXPECT_EQ(count_in_box(got, near_face_lo, near_face_hi), count_in_box(c, near_face_lo, near_face_hi))
      << "the near face inside the box not added";
  EXPECT_EQ(count_in_box(got, wall_lo, wall_hi), 0u) << "wall added";

  // leak_growth = base: only what lies below the found part's lowest points.
  segment::CompletionConfig base_only;
  base_only.leak_growth = segment::LeakGrowth::base;
  segment::CompletionStats st_base;
  const ObjectSet out_base = segment::complete_objects(in, s.missions, base_only, &st_base);
  ASSERT_EQ(st_base.object_notes.size(), 1u);
  EXPECT_NE(st_base.object_notes[0].find("only its base added"), std::string::npos) << st_base.object_notes[0];
  const auto& got_base = out_base.objects[0].points;
  EXPECT_GT(count_in_box(got_base, {1.55f, 0.f, 0.03f}, {1.6f, 0.4f, 0.12f}), 0u) << "base not added";
  EXPECT_EQ(count_in_box(got_base, near_face_lo, near_face_hi), 0u);
  EXPECT_EQ(count_in_box(got_base, wall_lo, wall_hi), 0u) << "wall added";
}

TEST(SegmentComplete, PhantomChangeOnStaticFurnitureStaysASliver) {
  // Residual misalignment reports the static box above 20 cm (in both
  // missions, unmoved) as change in B: completing it would report the whole
  // box. Every neighbouring mission holds what it would add, so static_check
  // leaves it out; without the check the box is swallowed.
  const Scene s = make_scene();
  const PointSet& c = s.cloud[1];
  const ObjectSet in = one_object(c, 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 2.49f && p.y() <= 0.51f && p.z() > 0.2f;
  });
  const size_t detected = in.objects[0].points.size();
  const size_t base = count_in_box(c, {2.5f, 0.f, 0.03f}, {3.0f, 0.5f, 0.19f});
  ASSERT_GT(base, 50u);

  segment::CompletionConfig off;
  off.static_check = false;
  const ObjectSet grown = segment::complete_objects(in, s.missions, off);
  EXPECT_EQ(count_in_box(grown.objects[0].points, {2.5f, 0.f, 0.03f}, {3.0f, 0.5f, 0.19f}), base);

  segment::CompletionStats st;
  const ObjectSet kept = segment::complete_objects(in, s.missions, {}, &st);
  EXPECT_EQ(kept.objects[0].points.size(), detected);
  EXPECT_GE(st.points_static, base);
}

TEST(SegmentComplete, ObjectsStandingOnTheFloorGetItsHeight) {
  // The scene's floor is z = 0, lifted by 0.7 m here so the height is not 0
  // by accident. An object whose lowest point is over 0.3 m above the floor
  // (a box on a table) gets none: what it stands on is not the floor.
  Scene s = make_scene();
  for (int m = 0; m < 2; ++m) {
    PointSet lifted = s.cloud[m];
    for (auto& p : lifted.xyz) p.z() += 0.7f;
    s.cloud[m] = lifted;
    s.missions.missions[size_t(m)].scans[0].points = std::make_shared<const PointSet>(lifted);
  }
  ObjectSet in = one_object(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
    return p.x() >= 0.99f && p.x() <= 1.61f && p.y() <= 0.41f && p.z() > 0.82f;
  });
  in.objects.push_back(object_where(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
    return p.x() >= 2.49f && p.y() <= 0.51f && p.z() > 1.1f;  // top of the static box only
  }));
  in.objects.back().id = 1;
  segment::CompletionConfig c;
  c.self_complete = false;  // the floor is measured without self-completion too
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  EXPECT_NEAR(out.objects[0].floor_z, 0.7f, 0.01f);
  EXPECT_TRUE(std::isnan(out.objects[1].floor_z));
  EXPECT_EQ(st.floors, 1u);
  EXPECT_TRUE(std::isnan(in.objects[0].floor_z)) << "the input is not touched";
}

// The difference cut the moved box of A into two clusters interleaved in one
// box (its top face's middle strip apart from the rest). Growth never takes
// another object's points, so without rule 6 they would stay two objects.
TEST(SegmentComplete, FragmentInsideALargerObjectsBoxJoinsIt) {
  const Scene s = make_scene();
  auto in_box = [](const Eigen::Vector3f& p) {
    return p.x() >= 0.99f && p.x() <= 1.61f && p.y() <= 0.41f && p.z() > 0.05f;
  };
  auto strip = [](const Eigen::Vector3f& p) { return p.z() > 0.79f && p.x() > 1.2f && p.x() < 1.4f; };
  ObjectSet in;
  in.missions = {"A", "B"};
  in.objects.push_back(object_where(s.cloud[0], 0, [&](const Eigen::Vector3f& p) { return in_box(p) && strip(p); }));
  in.objects.push_back(object_where(s.cloud[0], 0, [&](const Eigen::Vector3f& p) { return in_box(p) && !strip(p); }));
  // The static box of B, whole: beside the others, in no larger box.
  in.objects.push_back(object_where(s.cloud[1], 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 2.49f && p.z() > 0.05f && p.x() <= 3.01f && p.y() <= 0.51f;
  }));
  for (int i = 0; i < 3; ++i) in.objects[size_t(i)].id = 10 + i;
  const size_t strip_points = in.objects[0].points.size(), rest = in.objects[1].points.size();
  ASSERT_GT(strip_points, 5u);

  segment::CompletionConfig on;
  on.join_fragments = false;  // rule 6 alone (rule 1 may pair the moved box with B's static one)
  segment::CompletionConfig off = on;
  off.nested_share = 0.0;
  EXPECT_EQ(segment::complete_objects(in, s.missions, off).objects.size(), 3u);

  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, on, &st);
  ASSERT_EQ(out.objects.size(), 2u);
  EXPECT_EQ(st.absorbed, 1u);
  EXPECT_EQ(out.objects[0].id, 0);  // renumbered in order
  EXPECT_EQ(out.objects[1].id, 1);
  EXPECT_EQ(out.objects[0].mission, 0u);
  EXPECT_GE(out.objects[0].points.size(), strip_points + rest);
  EXPECT_EQ(count_in_box(out.objects[0].points, {1.2f, 0.f, 0.79f}, {1.4f, 0.4f, 0.81f}),
            count_in_box(s.cloud[0], {1.2f, 0.f, 0.79f}, {1.4f, 0.4f, 0.81f}));
  EXPECT_EQ(out.objects[1].mission, 1u);
  EXPECT_EQ(count_in_box(out.objects[1].points, {1.0f, 0.f, 0.f}, {1.9f, 0.4f, 0.8f}), 0u);
  std::set<uint32_t> idx(out.objects[0].points.index.begin(), out.objects[0].points.index.end());
  EXPECT_EQ(idx.size(), out.objects[0].points.size()) << "a point twice";
}

// Rule 0: a cluster of floor points (ground the difference flagged, as
// grazing beams do outdoors) is no object. It is dropped before pairing:
// beside A's sliver it is nearer than B's sliver and would otherwise take
// the pair, so the short move would not be completed. A low object (12 cm:
// the step rounds the 10 cm asked for; a pallet's height is 15) stays.
TEST(SegmentComplete, TheFloorItselfIsNoObject) {
  Scene s = make_scene();
  add_box_surface(s.cloud[1], {3.2f, 1.5f, 0.f}, {3.8f, 2.1f, 0.1f}, kStep);
  for (size_t i = 0; i < s.cloud[1].size(); ++i) s.cloud[1].index[i] = uint32_t(i);
  s.missions.missions[1].scans[0].points = std::make_shared<const PointSet>(s.cloud[1]);
  s.missions.missions[1].scans[0].points_in_file = uint32_t(s.cloud[1].size());
  ObjectSet in = slivers(s);
  in.objects.push_back(object_where(s.cloud[1], 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 1.0f && p.x() <= 1.25f && p.y() >= 0.5f && p.y() <= 0.9f && std::abs(p.z()) < 0.005f;
  }));
  in.objects.push_back(object_where(s.cloud[1], 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 3.19f && p.y() >= 1.49f && p.z() > 0.05f;
  }));
  for (size_t i = 0; i < in.objects.size(); ++i) in.objects[i].id = int(i);
  ASSERT_GT(in.objects[2].points.size(), 20u);
  ASSERT_GT(in.objects[3].points.size(), 20u);

  segment::CompletionConfig off;
  off.floor_share = 0.0;
  off.thin_surface_sides = 0;  // the floor patch is also a thin patch of a larger surface
  off.pair_retry = false;       // (with it the refused floor pair frees the sliver for B's)
  segment::CompletionStats st_off;
  EXPECT_EQ(segment::complete_objects(in, s.missions, off, &st_off).objects.size(), 4u);
  EXPECT_EQ(st_off.completed, 0u) << "the floor patch took the sliver's pair";

  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, {}, &st);
  ASSERT_EQ(out.objects.size(), 3u);
  EXPECT_EQ(st.floor_only, 1u);
  EXPECT_EQ(st.completed, 1u);
  for (size_t i = 0; i < out.objects.size(); ++i) {
    EXPECT_EQ(out.objects[i].id, int32_t(i)) << "renumbered in order";
    EXPECT_EQ(count_in_box(out.objects[i].points, {-1.f, -1.f, -0.01f}, {4.f, 3.f, 0.01f}), 0u) << "a floor point in an object";
  }
  EXPECT_GE(out.objects[2].points.size(), in.objects[3].points.size()) << "the low box is kept";
  EXPECT_EQ(count_in_box(out.objects[2].points, {3.2f, 1.5f, 0.f}, {3.8f, 2.1f, 0.13f}), out.objects[2].points.size());
}

// Rule 0 counts a point as floor only up to kFloorObjectHeight (0.1 m)
// above the floor, whatever the clearance: a rough floor's 4-sigma
// clearance (here forced to 0.3 m) must not turn a 0.2 m box into floor.
TEST(SegmentComplete, TheFloorRuleStopsATenthOfAMetreAboveTheFloor) {
  Scene s = make_scene();
  add_box_surface(s.cloud[1], {3.2f, 1.5f, 0.f}, {3.8f, 2.1f, 0.2f}, kStep);
  for (size_t i = 0; i < s.cloud[1].size(); ++i) s.cloud[1].index[i] = uint32_t(i);
  s.missions.missions[1].scans[0].points = std::make_shared<const PointSet>(s.cloud[1]);
  s.missions.missions[1].scans[0].points_in_file = uint32_t(s.cloud[1].size());
  ObjectSet in;
  in.missions = {"A", "B"};
  in.objects.push_back(object_where(s.cloud[1], 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 3.19f && p.y() >= 1.49f && p.z() > 0.005f;  // the low box, all of it under 0.3 m
  }));
  in.objects.push_back(object_where(s.cloud[1], 1, [](const Eigen::Vector3f& p) {
    return p.x() >= 0.f && p.x() <= 0.4f && p.y() >= 1.5f && p.y() <= 1.9f && std::abs(p.z()) < 0.005f;
  }));
  for (size_t i = 0; i < in.objects.size(); ++i) in.objects[i].id = int(i);
  ASSERT_GT(in.objects[0].points.size(), 50u);
  ASSERT_GT(in.objects[1].points.size(), 20u);
  // The share of the box's points under 0.1 m is what the cap leaves: under floor_share.
  size_t under = 0;
  for (const auto& p : in.objects[0].points.xyz) under += p.z() < 0.1f;
  ASSERT_LT(double(under), 0.9 * double(in.objects[0].points.size()));

  segment::CompletionConfig c;
  c.floor_clearance = 0.3;
  c.self_complete = false;
  c.thin_height = 0.0;
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  EXPECT_EQ(st.floor_only, 1u) << "the floor patch is still floor";
  ASSERT_EQ(out.objects.size(), 1u);
  EXPECT_EQ(out.objects[0].points.size(), in.objects[0].points.size()) << "the 0.2 m box is kept";
}

// Rule 0b: a thin cluster every neighbouring mission also holds is an
// unchanged horizontal surface (the static box's top, as grazing beams flag
// table tops); a thin cluster the other mission does not hold (the moved
// box's top where B has nothing) is kept.
TEST(SegmentComplete, UnchangedThinSurfacesAreDropped) {
  const Scene s = make_scene();
  ObjectSet in;
  in.missions = {"A", "B"};
  in.objects.push_back(object_where(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
    return p.x() >= 2.49f && p.y() <= 0.51f && p.z() > 0.59f;  // the static box's top
  }));
  in.objects.push_back(object_where(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
    return p.x() >= 0.99f && p.x() <= 1.19f && p.y() <= 0.41f && p.z() > 0.79f;  // A's moved box, top
  }));
  for (size_t i = 0; i < in.objects.size(); ++i) in.objects[i].id = int(i);
  ASSERT_GT(in.objects[0].points.size(), 20u);
  ASSERT_GT(in.objects[1].points.size(), 10u);
  segment::CompletionConfig c;
  c.self_complete = false;  // keep the kept object as it came
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, c, &st);
  EXPECT_EQ(st.thin_static, 1u);
  EXPECT_EQ(st.thin_surface, 0u);  // the moved top's sliver continues on one side only
  ASSERT_EQ(out.objects.size(), 1u);
  EXPECT_EQ(out.objects[0].id, 0);
  EXPECT_EQ(out.objects[0].points.size(), in.objects[1].points.size());
  c.thin_height = 0.0;
  EXPECT_EQ(segment::complete_objects(in, s.missions, c).objects.size(), 2u);
}

// A shelf 2 x 1 m at 0.2 m, seen by both missions, but the other mission's
// beams grazed a patch of it without hitting it (a sparse scanner): the
// patch came out as change in mission A. A continues the shelf on all four
// sides of the patch: dropped. A cart's deck at 0.5 m that B no longer
// has stands free: kept.
TEST(SegmentComplete, ThinPatchesOfALargerSurfaceAreDropped) {
  auto in_hole = [](float x, float y) { return x > 0.8f && x < 1.2f && y > 0.3f && y < 0.7f; };
  auto in_deck = [](float x, float y) { return x > 2.6f && x < 3.1f && y > 0.0f && y < 0.4f; };
  MissionSet missions;
  PointSet cloud[2];
  for (int m = 0; m < 2; ++m) {
    PointSet& c = cloud[m];
    auto add = [&](float x, float y, float z) {
      c.xyz.emplace_back(x, y, z);
      c.scan.push_back(0);
      c.index.push_back(uint32_t(c.index.size()));
    };
    for (float x = -1.f; x <= 4.f; x += kStep)
      for (float y = -1.f; y <= 2.f; y += kStep) {
        add(x, y, 0.f);  // floor
        const bool on_shelf = x >= 0.f && x <= 2.f && y >= 0.f && y <= 1.f;
        if (on_shelf && !(m == 1 && in_hole(x, y))) add(x, y, 0.2f);
        if (m == 0 && in_deck(x, y)) add(x, y, 0.5f);  // the deck, A only
      }
    add_mission(missions, m == 0 ? "A" : "B", c);
  }
  ObjectSet in;
  in.missions = {"A", "B"};
  in.objects.push_back(object_where(cloud[0], 0, [&](const Eigen::Vector3f& p) {
    return p.z() > 0.1f && p.z() < 0.3f && in_hole(p.x(), p.y());
  }));
  in.objects.push_back(object_where(cloud[0], 0, [&](const Eigen::Vector3f& p) {
    return p.z() > 0.4f && in_deck(p.x(), p.y());
  }));
  for (size_t i = 0; i < in.objects.size(); ++i) in.objects[i].id = int(i);
  ASSERT_GT(in.objects[0].points.size(), 20u);
  ASSERT_GT(in.objects[1].points.size(), 20u);
  segment::CompletionConfig c;
  c.self_complete = false;
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, missions, c, &st);
  EXPECT_EQ(st.thin_static, 0u);  // B does not hold the patch: the older rule keeps it
  EXPECT_EQ(st.thin_surface, 1u);
  ASSERT_EQ(out.objects.size(), 1u);
  EXPECT_EQ(out.objects[0].points.size(), in.objects[1].points.size());  // the deck
  c.thin_surface_sides = 0;
  EXPECT_EQ(segment::complete_objects(in, missions, c).objects.size(), 2u);
}

namespace {

// A scene (Scene's layout) with a floor z = 0 over [-1, 4] x [-1, 2] in
// missions A and B; in A only a table (top [0, 1.2] x [0, 0.8] at
// 0.70-0.74 m, four 6 cm legs inset 5 cm) and two boxes on a bench; the
// bench ([2.0, 3.6] x [0, 0.4], 0.4 m high) in both.
Scene make_table_scene() {
  Scene s;
  for (int m = 0; m < 2; ++m) {
    PointSet& c = s.cloud[m];
    add_floor(c, -1.f, 4.f, -1.f, 2.f);
    add_box_surface(c, {2.0f, 0.f, 0.f}, {3.6f, 0.4f, 0.4f}, kStep);
    if (m == 0) {
      add_box_surface(c, {0.f, 0.f, 0.70f}, {1.2f, 0.8f, 0.74f}, kStep);
      for (float x : {0.05f, 1.09f})
        for (float y : {0.05f, 0.69f}) add_box_surface(c, {x, y, 0.f}, {x + 0.06f, y + 0.06f, 0.70f}, 0.02f);
      add_box_surface(c, {2.05f, 0.05f, 0.4f}, {2.35f, 0.35f, 0.7f}, kStep);
      add_box_surface(c, {3.25f, 0.05f, 0.4f}, {3.55f, 0.35f, 0.7f}, kStep);
    }
    for (size_t i = 0; i < c.size(); ++i) c.index[i] = uint32_t(i);
    add_mission(s.missions, m == 0 ? "A" : "B", c);
  }
  return s;
}

}  // namespace

TEST(SegmentComplete, ObjectsConnectedOverChangedPointsAreJoined) {
  // The difference found the removed table's legs (10-60 cm) but not its
  // top: four clusters, joined over the top, which B does not hold.
  const Scene s = make_table_scene();
  std::vector<Object> legs;
  for (float x : {0.05f, 1.09f})
    for (float y : {0.05f, 0.69f})
      legs.push_back(object_where(s.cloud[0], 0, [&](const Eigen::Vector3f& p) {
        return p.x() >= x - 1e-3f && p.x() <= x + 0.061f && p.y() >= y - 1e-3f && p.y() <= y + 0.061f &&
               p.z() > 0.1f && p.z() < 0.6f;
      }));
  const ObjectSet in = object_set(legs);
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, {}, &st);
  EXPECT_EQ(st.connected, 3u);
  ASSERT_EQ(out.objects.size(), 1u);
  EXPECT_EQ(out.objects[0].id, 0);
  const Eigen::Vector3f top_lo{0.f, 0.f, 0.70f}, top_hi{1.2f, 0.8f, 0.74f};
  EXPECT_EQ(count_in_box(out.objects[0].points, top_lo, top_hi), count_in_box(s.cloud[0], top_lo, top_hi));
  EXPECT_EQ(count_in_box(out.objects[0].points, {-1.f, -1.f, -0.01f}, {4.f, 2.f, 0.01f}), 0u) << "floor points added";
  size_t joined_notes = 0;
  for (const auto& note : st.object_notes) joined_notes += note.find(": joined, connected over ") != std::string::npos;
  EXPECT_EQ(joined_notes, 3u);

  segment::CompletionConfig off;
  off.join_connected = false;
  segment::CompletionStats st_off;
  EXPECT_EQ(segment::complete_objects(in, s.missions, off, &st_off).objects.size(), 4u);
  EXPECT_EQ(st_off.connected, 0u);
}

TEST(SegmentComplete, ObjectsConnectedOnlyOverUnchangedPointsStayApart) {
  // Two boxes taken off a bench that stays: the bench connects them, but B
  // holds it, so they are two objects.
  const Scene s = make_table_scene();
  const ObjectSet in = object_set({object_where(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
                                     return p.x() >= 2.05f && p.x() <= 2.351f && p.z() > 0.45f && p.z() < 0.71f;
                                   }),
                                   object_where(s.cloud[0], 0, [](const Eigen::Vector3f& p) {
                                     return p.x() >= 3.25f && p.x() <= 3.551f && p.z() > 0.45f && p.z() < 0.71f;
                                   })});
  ASSERT_LT(lista::geometry::box_gap(in.objects[0], in.objects[1]), 1.0f);
  segment::CompletionStats st;
  const ObjectSet out = segment::complete_objects(in, s.missions, {}, &st);
  EXPECT_EQ(st.connected, 0u);
  EXPECT_EQ(out.objects.size(), 2u);
  bool refused = false;
  for (const auto& note : st.object_notes)
    refused |= note.rfind("objects 0 and 1: not joined, connected over points held unchanged elsewhere", 0) == 0;
  EXPECT_TRUE(refused);
}
