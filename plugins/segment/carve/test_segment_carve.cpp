// segment.carve: a crate seen whole in mission 0 and, turned and moved, in
// mission 1 against a taller shelf that changed too (one cluster there).
#include "carve_rule.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

#include <cmath>

using namespace test_support;

namespace {

constexpr float kStep = 0.03f;

// A box's surface as a scan sees it: no bottom face.
void add_box(lista::PointSet& s, Eigen::Vector3f lo, Eigen::Vector3f hi) {
  lista::PointSet all;
  add_box_surface(all, lo, hi, kStep);
  for (size_t i = 0; i < all.size(); ++i)
    if (all.xyz[i].z() > lo.z() + 1e-3f) s.push_back_from(all, i);
  for (size_t i = 0; i < s.size(); ++i) s.index[i] = uint32_t(i);
}

// Crate [0, 0.6] x [0, 0.5] x [0, 0.5] turned by `yaw` about its centre and
// moved by `at` (mission 0's template).
lista::Object crate(uint32_t mission, float yaw, Eigen::Vector2f at, float height = 0.5f) {
  lista::Object o;
  o.mission = mission;
  add_box(o.points, {0.f, 0.f, 0.f}, {0.6f, 0.5f, height});
  const float c = std::cos(yaw), s = std::sin(yaw);
  for (auto& p : o.points.xyz) {
    const Eigen::Vector2f q = p.head<2>() - Eigen::Vector2f(0.3f, 0.25f);
    p.head<2>() = Eigen::Vector2f(c * q.x() - s * q.y(), s * q.x() + c * q.y()) + at;
  }
  o.update_geometry();
  return o;
}

// Mission 1's cluster: the crate axis-aligned at the origin, touching a shelf
// [0.6, 1.0] x [-0.2, 0.8] x [0, shelf_height] beside it.
lista::Object crate_against_shelf(float shelf_height, size_t* crate_points) {
  lista::Object o;
  o.mission = 1;
  add_box(o.points, {0.f, 0.f, 0.f}, {0.6f, 0.5f, 0.5f});
  *crate_points = o.points.size();
  add_box(o.points, {0.6f, -0.2f, 0.f}, {1.0f, 0.8f, shelf_height});
  o.update_geometry();
  return o;
}

lista::ObjectSet set_of(std::vector<lista::Object> objects) {
  lista::ObjectSet s;
  s.missions = {"A", "B"};
  s.objects = std::move(objects);
  s.renumber();
  return s;
}

size_t count_inside(const lista::Object& o, Eigen::Vector3f lo, Eigen::Vector3f hi) {
  size_t n = 0;
  for (const auto& p : o.points.xyz)
    n += (p.array() >= lo.array() - 1e-4f).all() && (p.array() <= hi.array() + 1e-4f).all();
  return n;
}

}  // namespace

TEST(SegmentCarve, CutsTheCrateOutOfTheClusterItTouches) {
  size_t crate_points = 0;
  const lista::ObjectSet in =
      set_of({crate(0, 0.52f, {4.f, 2.f}), crate_against_shelf(1.2f, &crate_points)});
  lista::segment::CarveStats st;
  const lista::ObjectSet out = lista::segment::carve_objects(in, {}, &st);
  EXPECT_EQ(st.carved, 1u);
  ASSERT_EQ(out.objects.size(), 3u);
  EXPECT_EQ(out.objects[0].points.size(), in.objects[0].points.size()) << "the template is unchanged";
  const lista::Object &carved = out.objects[1], &rest = out.objects[2];
  EXPECT_EQ(carved.mission, 1u);
  EXPECT_EQ(rest.mission, 1u);
  EXPECT_EQ(carved.id, 1);
  EXPECT_EQ(rest.id, 2);
  // Every point goes to one side; the crate's side is the crate and what lies
  // within the tolerance of it (8 cm, up to a 5 cm grid cell more): the
  // shelf's face against it.
  EXPECT_EQ(carved.points.size() + rest.points.size(), in.objects[1].points.size());
  EXPECT_EQ(count_inside(carved, {-0.13f, -0.13f, 0.f}, {0.73f, 0.63f, 0.63f}), carved.points.size()) << "a far shelf point carved";
  EXPECT_GE(carved.points.size(), size_t(0.9 * double(crate_points)));
  EXPECT_NEAR(rest.bbox_max.z(), 1.2f, 1e-4f);
  EXPECT_EQ(count_inside(rest, {0.f, 0.f, 0.f}, {0.55f, 0.5f, 0.5f}), 0u) << "crate points left in the shelf";
}

TEST(SegmentCarve, ObjectsAsTallAsEachOtherStayWhole) {
  // A shelf as tall as the crate: the cut might run through one object's top.
  size_t crate_points = 0;
  const lista::ObjectSet in = set_of({crate(0, 0.52f, {4.f, 2.f}), crate_against_shelf(0.5f, &crate_points)});
  lista::segment::CarveStats st;
  EXPECT_EQ(lista::segment::carve_objects(in, {}, &st).objects.size(), 2u);
  EXPECT_EQ(st.fitted, 1u) << "it fits; the height check keeps it whole";
  EXPECT_EQ(st.carved, 0u);
  lista::segment::CarveConfig no_step;
  no_step.min_height_step = 0.0;
  EXPECT_EQ(lista::segment::carve_objects(in, no_step).objects.size(), 3u);
}

TEST(SegmentCarve, AShapeThatDoesNotFitCutsNothing) {
  // A lower box (0.3 m): its top lies where the cluster has no points.
  size_t crate_points = 0;
  const lista::ObjectSet in =
      set_of({crate(0, 0.52f, {4.f, 2.f}, 0.3f), crate_against_shelf(1.2f, &crate_points)});
  lista::segment::CarveStats st;
  const lista::ObjectSet out = lista::segment::carve_objects(in, {}, &st);
  EXPECT_EQ(st.candidates, 1u);
  EXPECT_EQ(st.fitted, 0u);
  ASSERT_EQ(out.objects.size(), 2u);
  EXPECT_EQ(out.objects[1].points.size(), in.objects[1].points.size());
}

TEST(SegmentCarve, OnlyNeighbouringMissionsAreTemplates) {
  size_t crate_points = 0;
  lista::ObjectSet in = set_of({crate(0, 0.52f, {4.f, 2.f}), crate_against_shelf(1.2f, &crate_points)});
  in.missions.push_back("C");
  in.objects[1].mission = 2;  // two missions apart
  lista::segment::CarveStats st;
  EXPECT_EQ(lista::segment::carve_objects(in, {}, &st).objects.size(), 2u);
  EXPECT_EQ(st.candidates, 0u);
}

TEST(SegmentCarve, SameResultForAnyOrderAndThreadCount) {
  size_t crate_points = 0;
  const lista::ObjectSet a = set_of({crate(0, 0.52f, {4.f, 2.f}), crate_against_shelf(1.2f, &crate_points)});
  const lista::ObjectSet b = set_of({a.objects[1], a.objects[0]});
  lista::segment::CarveConfig one, two;
  two.threads = 2;
  const lista::ObjectSet ra = lista::segment::carve_objects(a, one), rb = lista::segment::carve_objects(b, two);
  ASSERT_EQ(ra.objects.size(), 3u);
  ASSERT_EQ(rb.objects.size(), 3u);
  // b lists the cluster first: its two parts come first, then the template.
  EXPECT_EQ(ra.objects[1].points.index, rb.objects[0].points.index);
  EXPECT_EQ(ra.objects[2].points.index, rb.objects[1].points.index);
  EXPECT_EQ(ra.objects[0].points.index, rb.objects[2].points.index);
}

TEST(SegmentCarve, StageDeclaresItsParametersAndRuns) {
  size_t crate_points = 0;
  lista::ObjectSet in = set_of({crate(0, 0.52f, {4.f, 2.f}), crate_against_shelf(1.2f, &crate_points)});
  const auto out = run_stage("segment.carve", "objects", lista::Data::make(in), {{"min_fit", 0.9}});
  EXPECT_EQ(out.at("objects").as<lista::ObjectSet>().objects.size(), 3u);
  EXPECT_THROW(run_stage("segment.carve", "objects", lista::Data::make(in), {{"min_fit", 1.5}}), lista::Error);
  // Each host point marks a ball of (tolerance / voxel)^3 cells: bounded.
  EXPECT_THROW(run_stage("segment.carve", "objects", lista::Data::make(in), {{"tolerance", 0.4}}), lista::Error);
  // Objects from outside keep their optional channels through a cut.
  in.objects[1].points.label.assign(in.objects[1].points.size(), 7u);
  const auto labelled = run_stage("segment.carve", "objects", lista::Data::make(in));
  for (const auto& o : labelled.at("objects").as<lista::ObjectSet>().objects)
    if (o.mission == 1) {
      EXPECT_EQ(o.points.label.size(), o.points.size());
    }
}

TEST(SegmentCarve, OneTemplateTwoHostsGivesOneCutWhateverTheOrder) {
  // Two identical clusters (3 m apart) want the one crate: one is cut, the
  // same one for any object order and thread count.
  size_t crate_points = 0;
  lista::Object second = crate_against_shelf(1.2f, &crate_points);
  for (auto& p : second.points.xyz) p.x() += 3.f;
  for (auto& i : second.points.index) i += 100000;  // other points of the scan
  second.update_geometry();
  const lista::Object tmpl = crate(0, 0.52f, {4.f, 2.f}), first = crate_against_shelf(1.2f, &crate_points);
  lista::segment::CarveConfig two;
  two.threads = 2;
  std::vector<std::vector<uint32_t>> cut_host;
  for (const auto& order : {std::vector<lista::Object>{tmpl, first, second}, std::vector<lista::Object>{second, first, tmpl},
                            std::vector<lista::Object>{first, tmpl, second}})
    for (const lista::segment::CarveConfig& c : {lista::segment::CarveConfig{}, two}) {
      lista::segment::CarveStats st;
      const lista::ObjectSet out = lista::segment::carve_objects(set_of(order), c, &st);
      EXPECT_EQ(st.candidates, 2u);
      ASSERT_EQ(st.carved, 1u);
      ASSERT_EQ(out.objects.size(), 4u);
      for (const auto& o : out.objects)
        if (o.mission == 1 && o.bbox_max.z() < 0.6f) cut_host.push_back(o.points.index);  // the carved crate
    }
  ASSERT_EQ(cut_host.size(), 6u);
  for (const auto& c : cut_host) EXPECT_EQ(c, cut_host.front());
}
