// objreg::surface_shares, the shape check's measure of how much of one
// view lies on the other's surface (lista_objreg).
#include <lista_objreg/surface_share.hpp>

#include <gtest/gtest.h>

using lista::objreg::surface_shares;
using lista::objreg::SurfaceShareConfig;

namespace {

// A vertical face 1 m wide (x), seen by a sparse scanner: horizontal rings
// `spacing` apart starting at height `first`, up to `top`; points 1 cm apart
// along each ring; the face at y = `depth`.
std::vector<Eigen::Vector3f> rings(float first, float spacing, float top, float depth = 0.0f) {
  std::vector<Eigen::Vector3f> p;
  for (float z = first; z <= top + 1e-4f; z += spacing)
    for (float x = 0.0f; x <= 1.0f; x += 0.01f) p.emplace_back(x, depth, z);
  return p;
}

const Eigen::Isometry3d kIdentity = Eigen::Isometry3d::Identity();

}  // namespace

TEST(SurfaceShare, InterleavedRingsOfOneFaceLieOnEachOthersSurface) {
  // Two missions' rings 14 cm apart, offset by half a gap: every point is
  // 7 cm from the other's rings, beyond the 5 cm point test.
  const auto a = rings(0.0f, 0.14f, 1.4f), b = rings(0.07f, 0.14f, 1.33f);
  SurfaceShareConfig points_only;
  points_only.gap = 0.0;
  EXPECT_LT(surface_shares(a, b, kIdentity, points_only).source, 0.2);
  const SurfaceShareConfig cfg;  // gap 0.15
  EXPECT_GT(surface_shares(b, a, kIdentity, cfg).source, 0.97);
  // a's lowest and highest ring lie below / above b's: past its edge, not between its rings.
  const double share = surface_shares(a, b, kIdentity, cfg).source;
  EXPECT_GT(share, 0.8);
  EXPECT_LT(share, 0.9);
}

TEST(SurfaceShare, APartBeyondTheOtherViewsEdgeIsNotExplained) {
  // b is 0.56 m taller: its upper rings continue the plane, but nothing of a
  // surrounds them.
  const auto a = rings(0.0f, 0.14f, 0.84f), b = rings(0.07f, 0.14f, 1.4f);
  const double share = surface_shares(b, a, kIdentity, SurfaceShareConfig{}).source;
  EXPECT_GT(share, 0.5);
  EXPECT_LT(share, 0.65);  // 6 of b's 10 rings lie between a's
  // With a's rings 6 cm apart, two of them lie within the gap of b's ring
  // 7 cm above a's top: a surface, but below the point, not around it.
  const auto dense = rings(0.0f, 0.06f, 0.84f), above = rings(0.91f, 0.14f, 0.91f);
  EXPECT_EQ(surface_shares(above, dense, kIdentity, SurfaceShareConfig{}).source, 0.0);
}

TEST(SurfaceShare, AParallelFaceAFewCentimetresOffIsNotTheSameSurface) {
  // b's rings 4 cm in front of a's face: within 5 cm of a point only where a
  // ring of a is near in height; never within 2.5 cm of a's plane.
  const auto a = rings(0.0f, 0.14f, 1.4f), b = rings(0.07f, 0.14f, 1.33f, 0.04f);
  EXPECT_LT(surface_shares(b, a, kIdentity, SurfaceShareConfig{}).source, 0.05);
}

TEST(SurfaceShare, OneRingIsALineNotASurface) {
  const auto a = rings(0.5f, 1.0f, 0.5f), b = rings(0.57f, 1.0f, 0.57f);
  // 7 cm above a single ring: within the gap, but a line spans no plane.
  EXPECT_EQ(surface_shares(b, a, kIdentity, SurfaceShareConfig{}).source, 0.0);
}

TEST(SurfaceShare, TheTransformMovesTheFirstViewOntoTheSecond) {
  const auto a = rings(0.0f, 0.14f, 1.4f);
  std::vector<Eigen::Vector3f> moved;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(Eigen::Vector3d(2.0, -1.0, 0.0)).rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()));
  for (const auto& p : a) moved.push_back((t.cast<float>() * p));
  EXPECT_GT(surface_shares(a, moved, t, SurfaceShareConfig{}).source, 0.99);
  EXPECT_GT(surface_shares(a, moved, t, SurfaceShareConfig{}).target, 0.99);  // moved back by t^-1
  EXPECT_LT(surface_shares(a, moved, kIdentity, SurfaceShareConfig{}).source, 0.05);
  EXPECT_EQ(surface_shares({}, moved, t, SurfaceShareConfig{}).source, 0.0);
  EXPECT_EQ(surface_shares(a, {}, t, SurfaceShareConfig{}).target, 0.0);
}
