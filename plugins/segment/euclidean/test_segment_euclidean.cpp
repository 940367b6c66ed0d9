#include <lista_segmentation/voxel_clustering.hpp>
#include "euclidean_clustering.hpp"
#include <lista_testing/point_scenes.hpp>

#include <gtest/gtest.h>

using namespace test_support;

TEST(SegmentEuclidean, TwoBoxes30cmApartAreTwoClusters) {
  lista::PointSet s;
  add_box_surface(s, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, 0.05f);
  add_box_surface(s, {0.8f, 0, 0}, {1.3f, 0.5f, 0.5f}, 0.05f);
  lista::segment::EuclideanClusterConfig c;
  EXPECT_EQ(lista::segment::cluster_euclidean(s, c).size(), 2u);
  c.tolerance = 0.35;  // wider than the gap: one cluster
  EXPECT_EQ(lista::segment::cluster_euclidean(s, c).size(), 1u);
}

// segment.voxel (exact) must give the very same clusters as PCL.
TEST(SegmentEuclidean, SameClustersAsVoxelExactOnRandomBlobs) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> pos(-4.f, 4.f), rad(0.05f, 0.6f);
    lista::PointSet s;
    for (int b = 0; b < 25; ++b)
      add_blob(s, {pos(rng), pos(rng), pos(rng) * 0.3f}, rad(rng), 20 + int(rng() % 300), rng);
    for (double tol : {0.05, 0.1, 0.2}) {
      lista::segment::EuclideanClusterConfig ec;
      ec.tolerance = tol;
      ec.min_points = 5;
      lista::segmentation::VoxelClusterConfig vc;
      vc.tolerance = tol;
      vc.exact = true;
      vc.min_points = 5;
      auto a = lista::segment::cluster_euclidean(s, ec);
      auto b = lista::segmentation::cluster_voxels(s.xyz, vc);
      EXPECT_GT(a.size(), 1u);
      EXPECT_EQ(a, b) << "seed " << seed << " tolerance " << tol;
    }
  }
}

TEST(SegmentEuclidean, StageHonoursMinPoints) {
  std::mt19937 rng(3);
  lista::PointSet a;
  add_blob(a, {0, 0, 0}, 0.3f, 300, rng);
  add_blob(a, {3, 0, 0}, 0.1f, 8, rng);
  auto out = run_stage("segment.euclidean", "changes", lista::Data::make(missions({a, a})),
                       {{"min_points", int64_t(10)}});
  const auto& objects = out.at("objects").as<lista::ObjectSet>();
  ASSERT_EQ(objects.objects.size(), 2u);
  EXPECT_EQ(objects.objects[0].points.size(), 300u);
  EXPECT_EQ(objects.objects[1].mission, 1u);
  EXPECT_NE(objects.objects[0].id, objects.objects[1].id);
}
