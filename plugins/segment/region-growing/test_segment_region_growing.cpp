#include "region_growing.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

using namespace test_support;

namespace {
// A sphere surface on a Fibonacci lattice (even spacing, no randomness).
void add_sphere(lista::PointSet& s, Eigen::Vector3f c, float r, int n) {
  const float golden = float(M_PI) * (3.f - std::sqrt(5.f));
  for (int i = 0; i < n; ++i) {
    const float z = 1.f - 2.f * (float(i) + 0.5f) / float(n);
    const float rho = std::sqrt(1.f - z * z);
    add_point(s, c + r * Eigen::Vector3f(rho * std::cos(golden * float(i)), rho * std::sin(golden * float(i)), z));
  }
}
}  // namespace


TEST(SegmentRegionGrowing, SplitsABallRestingOnAPlane) {
  lista::PointSet s;
  for (float x = -1; x < 1.f; x += 0.025f)
    for (float y = -1; y < 1.f; y += 0.025f) add_point(s, {x, y, 0});
  const size_t plane = s.size();
  add_sphere(s, {0, 0, 0.3f}, 0.3f, 2500);  // touches the plane at the origin
  lista::segment::RegionGrowingConfig c;
  c.min_points = 300;  // the crease around the contact forms a small region of its own
  auto clusters = lista::segment::cluster_region_growing(s, c, 2);
  ASSERT_EQ(clusters.size(), 2u);
  // One region is (almost all) the plane, the other the ball.
  size_t plane_in_first = 0, ball_in_second = 0;
  for (auto i : clusters[0]) plane_in_first += i < plane;
  for (auto i : clusters[1]) ball_in_second += i >= plane;
  EXPECT_GT(plane_in_first, plane * 95 / 100);
  EXPECT_GT(ball_in_second, (s.size() - plane) * 90 / 100);
  // Without the curvature limit, growth runs through the contact: one region.
  c.curvature = 1.0;
  EXPECT_EQ(lista::segment::cluster_region_growing(s, c, 2).size(), 1u);
}

TEST(SegmentRegionGrowing, StageSeparatesDistantBlobsPerMission) {
  lista::PointSet a;
  add_sphere(a, {0, 0, 0}, 0.3f, 800);
  add_sphere(a, {2, 0, 0}, 0.3f, 800);
  auto out = run_stage("segment.region-growing", "changes", lista::Data::make(missions({a, a})));
  const auto& objects = out.at("objects").as<lista::ObjectSet>();
  ASSERT_EQ(objects.objects.size(), 4u);
  EXPECT_EQ(objects.objects[3].mission, 1u);
  EXPECT_NEAR(objects.objects[3].centroid.x(), 2.f, 0.01f);
}
