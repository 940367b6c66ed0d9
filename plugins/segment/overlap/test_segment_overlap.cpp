#include "overlap_rule.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

using namespace test_support;

namespace {
lista::Object box_object(uint32_t mission, Eigen::Vector3f lo, Eigen::Vector3f hi) {
  lista::Object o;
  o.mission = mission;
  add_box_surface(o.points, lo, hi, 0.04f);
  o.update_geometry();
  return o;
}
lista::ObjectSet make(std::vector<lista::Object> objects, size_t missions = 2) {
  lista::ObjectSet s;
  for (size_t m = 0; m < missions; ++m) s.missions.push_back("m" + std::to_string(m));
  s.objects = std::move(objects);
  s.renumber();
  return s;
}
}  // namespace

TEST(SegmentOverlap, MergesFragmentsOfAnObjectMovedLessThanItsSize) {
  // Mission 0: two fragments of one 1 m object; mission 1: the object whole.
  auto in = make({box_object(0, {0, 0, 0}, {0.4f, 0.6f, 0.6f}), box_object(0, {0.6f, 0, 0}, {1.0f, 0.6f, 0.6f}),
                  box_object(1, {0, 0, 0}, {1.0f, 0.6f, 0.6f})});
  lista::segment::OverlapStats st;
  auto out = lista::segment::merge_split_by_overlap(in, {}, &st);
  ASSERT_EQ(out.objects.size(), 2u);
  EXPECT_EQ(st.merged, 1u);
  EXPECT_EQ(out.objects[0].mission, 0u);
  EXPECT_EQ(out.objects[0].points.size(), in.objects[0].points.size() + in.objects[1].points.size());
  EXPECT_NEAR(out.objects[0].bbox_max.x(), 1.0f, 1e-4f);
  EXPECT_EQ(out.objects[1].points.size(), in.objects[2].points.size());
}

TEST(SegmentOverlap, PiecesFarApartAreObjectsNotFragments) {
  // Same, but the pieces are 0.8 m apart (more than merge_gap): they stay
  // apart, and the other mission's object is cut at them instead.
  auto in = make({box_object(0, {0, 0, 0}, {0.4f, 0.6f, 0.6f}), box_object(0, {1.2f, 0, 0}, {1.6f, 0.6f, 0.6f}),
                  box_object(1, {0, 0, 0}, {1.6f, 0.6f, 0.6f})});
  auto out = lista::segment::merge_split_by_overlap(in, {});
  ASSERT_EQ(out.objects.size(), 4u);
  EXPECT_EQ(out.objects[0].points.size(), in.objects[0].points.size());
  EXPECT_EQ(out.objects[1].points.size(), in.objects[1].points.size());
  EXPECT_EQ(out.objects[2].mission, 1u);
  EXPECT_EQ(out.objects[2].points.size() + out.objects[3].points.size(), in.objects[2].points.size());
  EXPECT_LE(out.objects[2].bbox_max.x(), 0.8f + 1e-4f);
  EXPECT_GE(out.objects[3].bbox_min.x(), 0.8f - 1e-4f);
}

TEST(SegmentOverlap, SplitsACompositeHeldApartInTheOtherMission) {
  // Mission 0: two touching boxes form one cluster; mission 1: two objects 0.44 m apart inside it.
  lista::Object composite = box_object(0, {0, 0, 0}, {0.48f, 0.48f, 0.48f});
  const size_t left = composite.points.size();
  add_box_surface(composite.points, {0.52f, 0, 0}, {1.0f, 0.48f, 0.48f}, 0.04f);
  composite.update_geometry();
  auto in = make({composite, box_object(1, {0, 0, 0}, {0.28f, 0.48f, 0.48f}),
                  box_object(1, {0.72f, 0, 0}, {1.0f, 0.48f, 0.48f})});
  lista::segment::OverlapStats st;
  auto out = lista::segment::merge_split_by_overlap(in, {}, &st);
  ASSERT_EQ(out.objects.size(), 4u);
  EXPECT_EQ(st.split, 1u);
  EXPECT_EQ(out.objects[0].points.size(), left);
  EXPECT_EQ(out.objects[1].points.size(), composite.points.size() - left);
  EXPECT_LT(out.objects[0].bbox_max.x(), 0.5f);
  EXPECT_GT(out.objects[1].bbox_min.x(), 0.5f);
  for (size_t i = 0; i < out.objects.size(); ++i) EXPECT_EQ(out.objects[i].id, int(i));
}

TEST(SegmentOverlap, LeavesUnrelatedAndNonConsecutiveObjectsAlone) {
  // Two fragments in mission 0 and the whole object in mission 2: not consecutive.
  auto in = make({box_object(0, {0, 0, 0}, {0.4f, 0.6f, 0.6f}), box_object(0, {0.6f, 0, 0}, {1.0f, 0.6f, 0.6f}),
                  box_object(1, {5, 5, 0}, {5.5f, 5.5f, 0.5f}), box_object(2, {0, 0, 0}, {1.0f, 0.6f, 0.6f})},
                 3);
  auto out = lista::segment::merge_split_by_overlap(in, {});
  ASSERT_EQ(out.objects.size(), 4u);
  for (size_t i = 0; i < 4; ++i) EXPECT_EQ(out.objects[i].points.size(), in.objects[i].points.size());
}

TEST(SegmentOverlap, StageRejectsObjectOfUnknownMission) {
  auto in = make({box_object(3, {0, 0, 0}, {1, 1, 1})});
  EXPECT_THROW(run_stage("segment.overlap", "objects", lista::Data::make(in)), lista::Error);
  auto ok = make({box_object(1, {0, 0, 0}, {1, 1, 1})});
  auto out = run_stage("segment.overlap", "objects", lista::Data::make(ok));
  EXPECT_EQ(out.at("objects").as<lista::ObjectSet>().objects.size(), 1u);
}

TEST(SegmentOverlap, DoesNotTrustStaleBounds) {
  // Bounds left at zero by an upstream stage: the rule recomputes them.
  auto in = make({box_object(0, {0, 0, 0}, {0.4f, 0.6f, 0.6f}), box_object(0, {0.6f, 0, 0}, {1.0f, 0.6f, 0.6f}),
                  box_object(1, {0, 0, 0}, {1.0f, 0.6f, 0.6f})});
  for (auto& o : in.objects) o.bbox_min = o.bbox_max = Eigen::Vector3f::Zero();
  EXPECT_EQ(lista::segment::merge_split_by_overlap(in, {}).objects.size(), 2u);
}
