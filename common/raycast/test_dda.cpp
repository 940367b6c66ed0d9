// The 3D DDA both volumetric backends walk: connectivity, length, the
// backward walk and its early stop; where a grazing beam stops being free.
#include <lista_raycast/dda.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using lista::raycast::ray_voxels;
using lista::raycast::Voxel;
using lista::raycast::voxel_of;
using lista::raycast::walk_ray;
using lista::raycast::walk_ray_back;

namespace {

std::vector<Voxel> forward(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  std::vector<Voxel> out;
  walk_ray(a, b, [&](const Voxel& v) { out.push_back(v); });
  return out;
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> random_rays(int n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-40.0, 40.0);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> rays;
  for (int i = 0; i < n; ++i) rays.push_back({{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  return rays;
}

}  // namespace

TEST(Dda, WalksAConnectedPathFromStartToBeforeEnd) {
  for (const auto& [a, b] : random_rays(500)) {
    const std::vector<Voxel> path = forward(a, b);
    ASSERT_EQ(static_cast<int>(path.size()), ray_voxels(a, b));
    if (path.empty()) continue;
    EXPECT_EQ(path.front(), voxel_of(a));
    for (size_t i = 1; i < path.size(); ++i) ASSERT_EQ((path[i] - path[i - 1]).cwiseAbs().sum(), 1);
    // The end voxel holds the return, so the walk stops one step short of it.
    EXPECT_EQ((voxel_of(b) - path.back()).cwiseAbs().sum(), 1);
  }
}

TEST(Dda, AxisAlignedAndDiagonalRays) {
  const std::vector<Voxel> x = forward({0.5, 0.5, 0.5}, {3.5, 0.5, 0.5});
  ASSERT_EQ(x.size(), 3u);
  EXPECT_EQ(x[2], Voxel(2, 0, 0));
  // Exact corner crossings: a tie steps the later axis first, every time.
  const std::vector<Voxel> d = forward({0.5, 0.5, 0.5}, {2.5, 2.5, 0.5});
  ASSERT_EQ(d.size(), 4u);
  EXPECT_EQ(d[1], Voxel(0, 1, 0));
  EXPECT_EQ(d[2], Voxel(1, 1, 0));
  EXPECT_EQ(d[3], Voxel(1, 2, 0));
  EXPECT_TRUE(forward({1.2, 3.4, 5.6}, {1.7, 3.1, 5.9}).empty());  // same voxel: nothing free
}

TEST(Dda, BackwardWalkIsTheForwardPathReversed) {
  // Walking the segment the other way could break an exact corner tie the
  // other way; random rays have none, so the paths must match step by step.
  for (const auto& [a, b] : random_rays(500)) {
    const std::vector<Voxel> path = forward(a, b);
    std::vector<Voxel> back;
    const uint32_t n = walk_ray_back(a, b, [&](const Voxel& v) {
      back.push_back(v);
      return true;
    });
    ASSERT_EQ(n, path.size());
    ASSERT_EQ(back.size(), path.size());
    for (size_t i = 0; i < path.size(); ++i) ASSERT_EQ(back[i], path[path.size() - 1 - i]) << "step " << i;
  }
}

TEST(Dda, BackwardWalkStopsWhenTheVisitorSaysSo) {
  const Eigen::Vector3d a(0.5, 0.5, 0.5), b(20.5, 0.5, 0.5);
  std::vector<Voxel> seen;
  const uint32_t n = walk_ray_back(a, b, [&](const Voxel& v) {
    seen.push_back(v);
    return v.x() > 15;
  });
  EXPECT_EQ(n, 5u);  // x = 19, 18, 17, 16, then 15 says stop
  ASSERT_EQ(seen.size(), 5u);
  EXPECT_EQ(seen.front(), Voxel(19, 0, 0));
  EXPECT_EQ(seen.back(), Voxel(15, 0, 0));
}

// beam_margin: a beam going down stops being free where it runs within
// graze_height above its return, at most graze_max short of it; level or
// rising beams, beams dropping less than graze_height and steep ones keep
// hit_margin.
TEST(Dda, GrazingBeamsStopShortOfTheirReturn) {
  const Eigen::Vector3d origin(0, 0, 1.2);
  const double margin = 0.25, h = 0.05, cap = 2.0;
  // 30 deg down: within 5 cm of the return's height for its last 10 cm, under hit_margin.
  const Eigen::Vector3d steep = origin + 2.0 * Eigen::Vector3d(std::cos(M_PI / 6), 0, -std::sin(M_PI / 6));
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, steep, margin, h, cap), margin);
  // 2 deg down (a floor 34 m away): 5 cm / sin(2 deg) = 1.43 m.
  const double a = 2.0 * M_PI / 180.0;
  const Eigen::Vector3d shallow = origin + 34.0 * Eigen::Vector3d(std::cos(a), 0, -std::sin(a));
  EXPECT_NEAR(lista::raycast::beam_margin(origin, shallow, margin, h, cap), h / std::sin(a), 1e-9);
  // 0.5 deg down: capped.
  const double b = 0.5 * M_PI / 180.0;
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, origin + 20.0 * Eigen::Vector3d(std::cos(b), 0, -std::sin(b)), margin, h, cap),
                   cap);
  // Level and rising beams, and graze_height 0: hit_margin only.
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, origin + Eigen::Vector3d(10, 0, 0), margin, h, cap), margin);
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, origin + Eigen::Vector3d(10, 0, 1), margin, h, cap), margin);
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, shallow, margin, 0.0, cap), margin);
  // Nearly level, dropping less than graze_height over 10 m (a wall at the
  // sensor's height): hit_margin, not graze_max; just over it: capped.
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, origin + Eigen::Vector3d(10, 0, -0.001), margin, h, cap), margin);
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, origin + Eigen::Vector3d(10, 0, -0.9 * h), margin, h, cap), margin);
  EXPECT_DOUBLE_EQ(lista::raycast::beam_margin(origin, origin + Eigen::Vector3d(10, 0, -2 * h), margin, h, cap), cap);
  // The free part ends that far before the return.
  const Eigen::Vector3d f = lista::raycast::free_end(origin, shallow, lista::raycast::beam_margin(origin, shallow, margin, h, cap));
  EXPECT_NEAR((shallow - f).norm(), h / std::sin(a), 1e-9);
  EXPECT_NEAR(f.z() - shallow.z(), h, 1e-9);
}
