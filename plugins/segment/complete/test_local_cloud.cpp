// LocalCloud's box queries and narrowing give what a plain pass over every
// point gives, on both of for_each_in's paths (voxel columns, every point).
#include "local_cloud.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace lista;
using namespace lista::segment::completion;

namespace {

// A mission of two scans at the origin: a floor 8 x 8 m with some clutter,
// random but fixed; its points are in the common frame already.
Mission cluttered_room() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> xy(-4.f, 4.f), z(-0.02f, 1.5f);
  Mission m;
  m.name = "A";
  for (int s = 0; s < 2; ++s) {
    PointSet pts;
    for (int i = 0; i < 20000; ++i) pts.xyz.emplace_back(xy(rng), xy(rng), i % 3 ? 0.01f * z(rng) : z(rng));
    pts.scan.assign(pts.size(), uint32_t(s));
    pts.index.resize(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) pts.index[i] = uint32_t(i);
    Scan scan;
    scan.points = std::make_shared<const PointSet>(pts);
    scan.points_in_file = uint32_t(pts.size());
    m.scans.push_back(scan);
  }
  return m;
}

Box box(float x0, float y0, float z0, float x1, float y1, float z1) {
  Box b;
  b.lo = {x0, y0, z0};
  b.hi = {x1, y1, z1};
  return b;
}

std::vector<uint32_t> inside(const LocalCloud& cloud, const Box& b) {
  std::vector<uint32_t> out;
  cloud.for_each_in(b, [&](uint32_t i) { out.push_back(i); });
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<uint32_t> inside_by_scan(const LocalCloud& cloud, const Box& b) {
  std::vector<uint32_t> out;
  for (size_t i = 0; i < cloud.points.size(); ++i)
    if (b.contains(cloud.points.xyz[i])) out.push_back(uint32_t(i));
  return out;
}

}  // namespace

TEST(LocalCloud, BoxQueriesFindExactlyThePointsInTheBox) {
  const LocalCloud cloud = gather(cluttered_room(), {box(-5, -5, -1, 5, 5, 2)}, 0.1f, 2);
  ASSERT_EQ(cloud.points.size(), 40000u);
  // Small boxes are read by voxel columns, boxes over most of the cloud point
  // by point; edges on and off the voxel grid, a flat and an empty box.
  for (const Box& b : {box(0.3f, -1.2f, 0.f, 1.1f, -0.45f, 0.8f), box(-2.f, -2.f, -0.1f, -1.f, -1.f, 0.05f),
                       box(-0.05f, -0.05f, 0.f, 0.05f, 0.05f, 2.f), box(-4.f, -4.f, 0.f, 4.f, 4.f, 0.f),
                       box(-4.f, -4.f, -1.f, 4.f, 4.f, 2.f), box(1.f, 1.f, 1.f, 0.f, 0.f, 0.f)})
    EXPECT_EQ(inside(cloud, b), inside_by_scan(cloud, b));
}

TEST(LocalCloud, NarrowingKeepsTheOrderAndAnIndexAsIfBuiltAgain) {
  const Mission mission = cluttered_room();
  const LocalCloud cloud = gather(mission, {box(-5, -5, -1, 5, 5, 2)}, 0.1f, 2);
  const std::vector<Box> regions = {box(-1.f, -1.f, -1.f, 0.5f, 0.5f, 2.f), box(2.f, 0.f, 0.f, 3.f, 3.f, 0.5f)};
  const LocalCloud narrowed = restrict_to(cloud, regions);
  LocalCloud rebuilt = gather(mission, regions, 0.1f, 1);
  EXPECT_EQ(narrowed.points.xyz, rebuilt.points.xyz);
  EXPECT_EQ(narrowed.points.index, rebuilt.points.index);
  EXPECT_EQ(narrowed.grid, rebuilt.grid);
  Floor a, b;
  ASSERT_TRUE(local_floor(narrowed, regions[1], 0.1, 0.02, a));
  ASSERT_TRUE(local_floor(rebuilt, regions[1], 0.1, 0.02, b));
  EXPECT_EQ(a.z, b.z);
  EXPECT_EQ(a.clear_z, b.clear_z);
}
