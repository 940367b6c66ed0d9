#include <lista_testing/point_scenes.hpp>
#include <lista_segmentation/voxel_clustering.hpp>

#include <gtest/gtest.h>

using namespace test_support;
using lista::segmentation::cluster_voxels;
using lista::segmentation::VoxelClusterConfig;

TEST(SegmentVoxel, TwoBoxes30cmApartAreTwoClusters) {
  lista::PointSet s;
  add_box_surface(s, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, 0.05f);
  const size_t first = s.size();
  add_box_surface(s, {0.8f, 0, 0}, {1.3f, 0.5f, 0.5f}, 0.05f);
  for (bool exact : {false, true}) {
    VoxelClusterConfig c;
    c.exact = exact;
    auto clusters = cluster_voxels(s.xyz, c);
    ASSERT_EQ(clusters.size(), 2u) << "exact=" << exact;
    EXPECT_EQ(clusters[0].size(), first);
    EXPECT_EQ(clusters[1].size(), s.size() - first);
  }
}

TEST(SegmentVoxel, VoxelModeJoinsWhatExactModeSplits) {
  // Two points 0.15 apart in adjacent voxels: voxel mode joins, exact does not.
  std::vector<Eigen::Vector3f> xyz = {{0.05f, 0.05f, 0.05f}, {0.18f, 0.05f, 0.05f}};
  VoxelClusterConfig c;
  c.min_points = 1;
  EXPECT_EQ(cluster_voxels(xyz, c).size(), 1u);
  c.exact = true;
  EXPECT_EQ(cluster_voxels(xyz, c).size(), 2u);
}

TEST(SegmentVoxel, MinAndMaxClusterSize) {
  std::mt19937 rng(1);
  lista::PointSet s;
  add_blob(s, {0, 0, 0}, 0.2f, 5, rng);    // tiny
  add_blob(s, {3, 0, 0}, 0.3f, 200, rng);  // medium
  add_blob(s, {6, 0, 0}, 0.5f, 2000, rng); // large
  VoxelClusterConfig c;
  c.tolerance = 0.2;
  c.min_points = 1;
  EXPECT_EQ(cluster_voxels(s.xyz, c).size(), 3u);
  c.min_points = 10;
  c.max_points = 1000;
  auto clusters = cluster_voxels(s.xyz, c);
  ASSERT_EQ(clusters.size(), 1u);
  EXPECT_EQ(clusters[0].size(), 200u);
}

TEST(SegmentVoxel, RejectsPointsOutsideTheGrid) {
  std::vector<Eigen::Vector3f> xyz = {{0, 0, 0}, {1e6f, 0, 0}};
  VoxelClusterConfig c;
  c.tolerance = 0.1;
  EXPECT_THROW(cluster_voxels(xyz, c), lista::Error);
}

TEST(SegmentVoxel, StageMakesObjectsPerMissionWithProvenance) {
  lista::PointSet a, b;
  add_box_surface(a, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, 0.05f, 3);
  add_box_surface(a, {2, 0, 0}, {2.5f, 0.5f, 0.5f}, 0.05f, 4);
  add_box_surface(b, {5, 5, 0}, {5.4f, 5.4f, 0.4f}, 0.05f, 9);
  add_point(b, {20, 20, 20});  // lone point: below min_points
  auto out = run_stage("segment.voxel", "changes", lista::Data::make(missions({a, b})));
  const auto& objects = out.at("objects").as<lista::ObjectSet>();
  ASSERT_EQ(objects.objects.size(), 3u);
  EXPECT_EQ(objects.missions.size(), 2u);
  std::set<int> ids;
  for (const auto& o : objects.objects) ids.insert(o.id);
  EXPECT_EQ(ids.size(), 3u);
  EXPECT_EQ(objects.objects[0].mission, 0u);
  EXPECT_EQ(objects.objects[2].mission, 1u);
  EXPECT_EQ(objects.objects[1].points.scan.front(), 4u);
  EXPECT_EQ(objects.objects[2].points.size(), b.size() - 1);
  EXPECT_NEAR(objects.objects[2].centroid.x(), 5.2f, 1e-3f);
  EXPECT_NEAR(objects.objects[2].bbox_max.z(), 0.4f, 1e-4f);
}

TEST(SegmentVoxel, ResultDoesNotDependOnThreads) {
  std::mt19937 rng(5);
  std::vector<lista::PointSet> sets(3);
  for (int m = 0; m < 3; ++m)
    for (int k = 0; k < 10; ++k)
      add_blob(sets[m], {float(k), float(m), 0}, 0.3f, 100, rng);
  auto one = run_stage("segment.voxel", "changes", lista::Data::make(missions(sets)), {}, 1);
  auto four = run_stage("segment.voxel", "changes", lista::Data::make(missions(sets)), {}, 4);
  const auto& a = one.at("objects").as<lista::ObjectSet>().objects;
  const auto& b = four.at("objects").as<lista::ObjectSet>().objects;
  ASSERT_EQ(a.size(), 30u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].points.index, b[i].points.index);
}

// A cluster most of whose points their own mission also saw free moved
// during the mission (a person walking by): a dynamic, not an object.
TEST(SegmentVoxel, ClustersMostlySeenFreeInTheirOwnMissionAreDynamics) {
  lista::PointSet a;
  add_box_surface(a, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, 0.05f, 3);  // a cabinet, removed
  const size_t cabinet = a.size();
  add_box_surface(a, {2, 0, 0}, {2.4f, 0.3f, 1.2f}, 0.05f, 4);  // a person walking by: legs seen through
  const size_t person = a.size() - cabinet;
  add_box_surface(a, {2.05f, 0.05f, 1.5f}, {2.35f, 0.25f, 1.8f}, 0.05f, 5);  // the torso: apart, never seen through
  const size_t torso = a.size() - cabinet - person;
  a.changed_against.assign(a.size(), lista::changed_against_next);
  // A few of the cabinet's points were grazed free too; most of the person's.
  for (size_t i = 0; i < cabinet; i += 5) a.changed_against[i] |= lista::seen_free_in_own_mission;
  for (size_t i = cabinet; i < cabinet + person; ++i)
    if (i % 4) a.changed_against[i] |= lista::seen_free_in_own_mission;
  ASSERT_EQ(cluster_voxels(a.xyz, VoxelClusterConfig{}).size(), 3u) << "cabinet, legs and torso apart";
  lista::PointSet b;
  add_box_surface(b, {5, 5, 0}, {5.4f, 5.4f, 0.4f}, 0.05f, 9);
  b.changed_against.assign(b.size(), lista::changed_against_previous);
  lista::BasicContext ctx("segment");
  auto out = run_stage("segment.voxel", "changes", lista::Data::make(missions({a, b})), {}, 2, &ctx);
  const auto& objects = out.at("objects").as<lista::ObjectSet>();
  ASSERT_EQ(objects.objects.size(), 2u);
  EXPECT_EQ(objects.objects[0].points.size(), cabinet);
  EXPECT_EQ(objects.objects[0].id, 0);
  EXPECT_EQ(objects.objects[1].id, 1);
  ASSERT_EQ(objects.dynamics.size(), 1u);
  EXPECT_EQ(objects.dynamics[0].mission, 0u);
  EXPECT_EQ(objects.dynamics[0].points, person + torso) << "the torso stands on the legs' footprint";
  EXPECT_NEAR(objects.dynamics[0].centroid.x(), 2.2f, 0.05f);
  EXPECT_NEAR(objects.dynamics[0].bbox_max.z(), 1.8f, 1e-4f);
  EXPECT_EQ(ctx.info.metrics.at("segment").at("dynamic_objects"), 1.0);
  EXPECT_EQ(ctx.info.metrics.at("segment").at("dynamic_points"), double(person + torso));
}
