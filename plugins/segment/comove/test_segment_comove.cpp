#include "comove_rule.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <lista_geometry/object_geometry.hpp>

using namespace test_support;

namespace {

// One object: an axis-aligned box's surface, turned by `yaw` about the
// origin and moved by `shift`.
lista::Object piece(uint32_t mission, Eigen::Vector3f lo, Eigen::Vector3f hi, float yaw, Eigen::Vector2f shift) {
  lista::Object o;
  o.mission = mission;
  add_box_surface(o.points, lo, hi, 0.02f);
  const Eigen::Matrix2f r = Eigen::Rotation2Df(yaw).toRotationMatrix();
  for (auto& p : o.points.xyz) p.head<2>() = r * p.head<2>() + shift;
  o.floor_z = 0.f;
  o.update_geometry();
  return o;
}

// The legs of a w x d table (5 cm posts, 0.72 m tall), each its own object.
std::vector<lista::Object> legs(uint32_t mission, float w, float d, float yaw, Eigen::Vector2f shift, int count = 4) {
  const Eigen::Vector2f corners[4] = {{0, 0}, {w, 0}, {w, d}, {0, d}};
  std::vector<lista::Object> out;
  for (int k = 0; k < count; ++k) {
    const Eigen::Vector3f lo(corners[k].x(), corners[k].y(), 0.f);
    out.push_back(piece(mission, lo, lo + Eigen::Vector3f(0.05f, 0.05f, 0.72f), yaw, shift));
  }
  return out;
}

lista::ObjectSet make(std::vector<std::vector<lista::Object>> groups, size_t missions = 2) {
  lista::ObjectSet s;
  for (size_t m = 0; m < missions; ++m) s.missions.push_back("m" + std::to_string(m));
  for (auto& g : groups)
    for (auto& o : g) s.objects.push_back(std::move(o));
  s.renumber();
  return s;
}

size_t points_of(const lista::ObjectSet& s, uint32_t mission) {
  size_t n = 0;
  for (const auto& o : s.objects) n += o.mission == mission ? o.points.size() : 0;
  return n;
}

}  // namespace

TEST(SegmentComove, LegsOfAMovedTableBecomeOneTableInEachMission) {
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f})});
  lista::segment::ComoveStats st;
  const auto out = lista::segment::join_comoving(in, {}, &st);
  ASSERT_EQ(out.objects.size(), 2u);
  EXPECT_EQ(st.joins, 2u);
  EXPECT_EQ(st.joined, 8u);
  for (uint32_t m = 0; m < 2; ++m) {
    EXPECT_EQ(out.objects[m].mission, m);
    EXPECT_EQ(out.objects[m].id, int(m));
    EXPECT_EQ(out.objects[m].points.size(), points_of(in, m));
    EXPECT_EQ(out.objects[m].floor_z, 0.f);
  }
  EXPECT_NEAR(out.objects[0].bbox_max.x(), in.objects[1].bbox_max.x(), 1e-4f);  // bounds recomputed
  EXPECT_NEAR(out.objects[0].bbox_max.y(), in.objects[2].bbox_max.y(), 1e-4f);
}

TEST(SegmentComove, LegsInAnotherLayoutStayApart) {
  // Mission 1's posts stand 2.0 x 0.3 m apart: no one motion carries the
  // first table's legs onto them.
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 2.0f, 0.3f, 0.7f, {3.f, 1.f})});
  EXPECT_EQ(lista::segment::join_comoving(in, {}).objects.size(), 8u);
}

TEST(SegmentComove, PiecesStandingWhereTheyWereAreNoMove) {
  // The same legs in both missions (and the table turned 180 degrees about
  // its middle lands on them too): nothing moved, nothing joins.
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.f, {0, 0})});
  EXPECT_EQ(lista::segment::join_comoving(in, {}).objects.size(), 8u);
}

TEST(SegmentComove, BulkyPiecesMovedTogetherAreSeparateObjects) {
  // Two crates moved side by side: not slender, so not pieces of one thing,
  // unless slender_ratio = 0 lets every piece take part.
  auto crates = [](uint32_t m, float yaw, Eigen::Vector2f shift) {
    return std::vector<lista::Object>{piece(m, {0, 0, 0}, {0.8f, 0.8f, 0.5f}, yaw, shift),
                                      piece(m, {1.2f, 0, 0}, {2.0f, 0.8f, 0.5f}, yaw, shift)};
  };
  auto in = make({crates(0, 0.f, {0, 0}), crates(1, 0.5f, {4.f, 0.f})});
  EXPECT_EQ(lista::segment::join_comoving(in, {}).objects.size(), 4u);
  lista::segment::ComoveConfig any;
  any.slender_ratio = 0;
  EXPECT_EQ(lista::segment::join_comoving(in, any).objects.size(), 2u);
}

TEST(SegmentComove, AJoinedObjectLongerThanMaxExtentIsRefused) {
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f})});
  lista::segment::ComoveConfig c;
  c.max_extent = 1.0;  // two legs of a short side still fit
  EXPECT_EQ(lista::segment::join_comoving(in, c).objects.size(), 4u);
  c.max_extent = 0.5;
  EXPECT_EQ(lista::segment::join_comoving(in, c).objects.size(), 8u);
}

TEST(SegmentComove, ALegTheOtherMissionDidNotSeeStaysApart) {
  // Mission 1 sees three legs: one of mission 0's has no evidence (which
  // one is open: a rectangle's L of three corners fits it turned 180
  // degrees too).
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f}, 3)});
  const auto out = lista::segment::join_comoving(in, {});
  ASSERT_EQ(out.objects.size(), 3u);
  EXPECT_EQ(out.objects[0].mission, 0u);
  EXPECT_EQ(out.objects[1].mission, 0u);
  const size_t a = out.objects[0].points.size(), b = out.objects[1].points.size();
  EXPECT_EQ(a + b, points_of(in, 0));
  EXPECT_LT(std::min(a, b), 500u);  // one leg
  EXPECT_GT(std::max(a, b), 1000u);  // three
  EXPECT_EQ(out.objects[2].points.size(), points_of(in, 1));
}

TEST(SegmentComove, JoinsChainOverThreeMissions) {
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f}),
                  legs(2, 1.2f, 0.6f, -0.4f, {0.f, 4.f})},
                 3);
  const auto out = lista::segment::join_comoving(in, {});
  ASSERT_EQ(out.objects.size(), 3u);
  for (uint32_t m = 0; m < 3; ++m) EXPECT_EQ(out.objects[m].points.size(), points_of(in, m));
}

TEST(SegmentComove, PiecesOnlyJoinWhenTheyChangedAgainstEachOther) {
  // The legs of mission 1 changed against mission 2 only (a third mission's
  // business): mission 0's legs have no partner.
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f})}, 3);
  for (auto& o : in.objects)
    o.points.changed_against.assign(o.points.size(), lista::changed_against_next);
  EXPECT_EQ(lista::segment::join_comoving(in, {}).objects.size(), 8u);
}

TEST(SegmentComove, NothingToJoinLeavesTheSetAsItWas) {
  // One mission, an empty set, and ids that are not 0..n-1: kept as given.
  auto one = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0})}, 1);
  for (auto& o : one.objects) o.id += 10;
  const auto out = lista::segment::join_comoving(one, {});
  ASSERT_EQ(out.objects.size(), 4u);
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(out.objects[k].id, one.objects[k].id);
  EXPECT_TRUE(lista::segment::join_comoving(make({}, 2), {}).objects.empty());
}

TEST(SegmentComove, AJoinedObjectTakesTheLowestKnownFloor) {
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f})});
  in.objects[0].floor_z = std::numeric_limits<float>::quiet_NaN();
  in.objects[1].floor_z = -0.02f;
  in.objects[4].floor_z = std::numeric_limits<float>::quiet_NaN();
  const auto out = lista::segment::join_comoving(in, {});
  ASSERT_EQ(out.objects.size(), 2u);
  EXPECT_EQ(out.objects[0].floor_z, -0.02f);
  EXPECT_EQ(out.objects[1].floor_z, 0.f);
}

TEST(SegmentComove, AGridOfPostsEndsTheSearchAtItsBudget) {
  // 12 x 12 posts 0.8 m apart in each mission, the second grid shifted by
  // half a step: every pair of pairs is a hypothesis. The search stops at
  // its budget and says so; what it joined keeps to max_extent.
  auto grid = [](uint32_t m, float shift) {
    std::vector<lista::Object> posts;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) {
        const Eigen::Vector3f lo(0.8f * i + shift, 0.8f * j + shift, 0.f);
        posts.push_back(piece(m, lo, lo + Eigen::Vector3f(0.06f, 0.06f, 1.0f), 0.f, {0, 0}));
      }
    return posts;
  };
  auto in = make({grid(0, 0.f), grid(1, 0.4f)});
  lista::segment::ComoveStats st;
  const auto out = lista::segment::join_comoving(in, {}, &st);
  EXPECT_EQ(st.searches_cut, std::vector<uint32_t>{0});
  for (const auto& o : out.objects)
    EXPECT_LE(lista::geometry::horizontal_extents(o.points.xyz).x(), 3.0f + 1e-3f);
}

TEST(SegmentComove, DoesNotTrustStaleBounds) {
  // Bounds and centroids left at zero by an upstream stage: recomputed.
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f})});
  for (auto& o : in.objects) o.bbox_min = o.bbox_max = o.centroid = Eigen::Vector3f::Zero();
  EXPECT_EQ(lista::segment::join_comoving(in, {}).objects.size(), 2u);
}

TEST(SegmentComove, StageReadsItsParameters) {
  auto in = make({legs(0, 1.2f, 0.6f, 0.f, {0, 0}), legs(1, 1.2f, 0.6f, 0.7f, {3.f, 1.f})});
  auto run = [&](std::map<std::string, lista::ParamValue> set) {
    return run_stage("segment.comove", "objects", lista::Data::make(in), set).at("objects").as<lista::ObjectSet>();
  };
  EXPECT_EQ(run({}).objects.size(), 2u);
  EXPECT_EQ(run({{"join_gap", 0.3}}).objects.size(), 8u);  // the legs stand 0.55 m apart
  EXPECT_THROW(run({{"cover_share", 1.5}}), lista::Error);
}
