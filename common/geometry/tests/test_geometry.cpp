// lista::geometry: box gaps, the yaw-invariant footprint, stations, order statistics.
#include <lista_geometry/object_geometry.hpp>
#include <lista_geometry/order_statistics.hpp>
#include <lista_geometry/radius_grid.hpp>
#include <lista_geometry/stations.hpp>
#include <lista_geometry/voxel_key.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace {

// Two walls of a 1.0 x 0.4 m box meeting at a corner (what one scan sees of
// it), 0.6 m high, turned by `yaw` and moved far from the origin.
std::vector<Eigen::Vector3f> corner_view(float yaw) {
  const Eigen::Matrix3f r = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i <= 100; ++i)
    for (int k = 0; k <= 6; ++k) {
      const float z = 0.1f * float(k);
      pts.push_back(r * Eigen::Vector3f(0.01f * float(i), 0.f, z) + Eigen::Vector3f(40.f, -25.f, 0.f));
      if (i <= 40) pts.push_back(r * Eigen::Vector3f(0.f, 0.01f * float(i), z) + Eigen::Vector3f(40.f, -25.f, 0.f));
    }
  return pts;
}

TEST(HorizontalExtents, AreTheBoxSidesOfAPartialViewWhateverTheYaw) {
  for (float yaw : {0.f, 0.7f, 2.2f, -1.3f}) {
    const Eigen::Vector2f e = lista::geometry::horizontal_extents(corner_view(yaw));
    // Principal axes of this L lean towards its diagonal and report about
    // 1.06 x 0.39; the footprint rectangle has the walls' lengths.
    EXPECT_NEAR(e[0], 1.0f, 1e-3f) << "yaw " << yaw;
    EXPECT_NEAR(e[1], 0.4f, 1e-3f) << "yaw " << yaw;
  }
}

TEST(HorizontalExtents, LinesFallBackToPrincipalAxesAndFewPointsAreZero) {
  std::vector<Eigen::Vector3f> line;
  for (int i = 0; i <= 10; ++i) line.emplace_back(0.1f * float(i), 0.1f * float(i), 0.5f);
  const Eigen::Vector2f e = lista::geometry::horizontal_extents(line);
  EXPECT_NEAR(e[0], std::sqrt(2.f), 1e-4f);
  EXPECT_NEAR(e[1], 0.f, 1e-4f);
  EXPECT_EQ(lista::geometry::horizontal_extents({{0, 0, 0}, {1, 1, 1}}), Eigen::Vector2f::Zero());
}

TEST(BoxGap, ZeroWhenTouchingElseTheDistanceBetweenBoxes) {
  lista::Object a, b;
  a.bbox_min = {0, 0, 0}, a.bbox_max = {1, 1, 1};
  b.bbox_min = {1, 0.5f, 0}, b.bbox_max = {2, 2, 1};
  EXPECT_FLOAT_EQ(lista::geometry::box_gap(a, b), 0.f);
  b.bbox_min = {4, 5, 0}, b.bbox_max = {5, 6, 1};
  EXPECT_FLOAT_EQ(lista::geometry::box_gap(a, b), 5.f);  // 3 along x, 4 along y
}

}  // namespace

TEST(VoxelKey, UnpacksToTheVoxelItWasPackedFromAndSortsByXThenYThenZ) {
  for (const Eigen::Vector3i& v : {Eigen::Vector3i(0, 0, 0), Eigen::Vector3i(-3, 7, -1),
                                  Eigen::Vector3i(1000000, -1000000, 12)})
    EXPECT_EQ(lista::geometry::voxel_of_key(lista::geometry::voxel_key(v)), v);
  EXPECT_LT(lista::geometry::voxel_key({-1, 5, 5}), lista::geometry::voxel_key({0, -5, -5}));
  EXPECT_LT(lista::geometry::voxel_key({0, -1, 5}), lista::geometry::voxel_key({0, 0, -5}));
  // A point just below a cell boundary and one just above it.
  EXPECT_EQ(lista::geometry::voxel_of_key(lista::geometry::voxel_key_of({-0.01, 0.19, 0.21}, 0.1)),
            Eigen::Vector3i(-1, 1, 2));
}

TEST(BoundingRectangle, CornersAndCentreFollowTheTurnedRectangle) {
  // A 2 x 1 m rectangle's outline, turned by 30 degrees about (5, 3).
  const double yaw = 0.5235987755982988;
  const Eigen::Rotation2Dd r(yaw);
  std::vector<Eigen::Vector3f> pts;
  for (int k = 0; k <= 40; ++k) {
    const double a = -1.0 + 2.0 * k / 40, b = -0.5 + 1.0 * k / 40;
    for (const Eigen::Vector2d& q : {Eigen::Vector2d(a, -0.5), Eigen::Vector2d(a, 0.5), Eigen::Vector2d(-1.0, b), Eigen::Vector2d(1.0, b)}) {
      const Eigen::Vector2d w = r * q + Eigen::Vector2d(5, 3);
      pts.emplace_back(float(w.x()), float(w.y()), 0.f);
    }
  }
  const auto rect = lista::geometry::min_perimeter_rectangle(pts);
  ASSERT_TRUE(rect.valid);
  EXPECT_NEAR(rect.centre.x(), 5.0, 1e-5);
  EXPECT_NEAR(rect.centre.y(), 3.0, 1e-5);
  // Every true corner is one of the four, and they go round.
  const auto c = rect.corners();
  for (const Eigen::Vector2d& q : {Eigen::Vector2d(-1, -0.5), Eigen::Vector2d(1, -0.5), Eigen::Vector2d(1, 0.5), Eigen::Vector2d(-1, 0.5)}) {
    const Eigen::Vector2d w = r * q + Eigen::Vector2d(5, 3);
    double nearest = 1e9;
    for (const auto& k : c) nearest = std::min(nearest, (k - w).norm());
    EXPECT_LT(nearest, 1e-5);
  }
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d e0 = c[(k + 1) % 4] - c[k], e1 = c[(k + 2) % 4] - c[(k + 1) % 4];
    EXPECT_GT(e0.x() * e1.y() - e0.y() * e1.x(), 0.0);  // counter-clockwise
  }
  EXPECT_NEAR((c[1] - c[0]).norm(), 2.0, 1e-5);  // first side along the long axis
}

TEST(RadiusGrid, FindsExactlyThePointsWithinTheRadiusAcrossCells) {
  std::vector<Eigen::Vector3f> xyz = {{0.09f, 0.f, 0.f}, {0.11f, 0.f, 0.f}, {-0.05f, 0.05f, 0.05f}, {0.3f, 0.f, 0.f}};
  lista::geometry::RadiusGrid grid(0.1f);
  for (uint32_t i = 0; i < xyz.size(); ++i) grid.add(xyz[i], i);
  std::vector<uint32_t> found;
  grid.for_near(xyz, Eigen::Vector3f(0.f, 0.f, 0.f), [&](uint32_t i) { found.push_back(i); });
  std::sort(found.begin(), found.end());
  EXPECT_EQ(found, (std::vector<uint32_t>{0, 2}));  // 0.09 and 0.087 m; 0.11 m is out
  EXPECT_TRUE(grid.any_near(xyz, Eigen::Vector3f(0.25f, 0.f, 0.f)));
  EXPECT_FALSE(grid.any_near(xyz, Eigen::Vector3f(0.f, 0.5f, 0.f)));
}

// Stations: scans farther apart than their points reach, or a single scan.
TEST(Stations, ScansFartherApartThanTheirPointsReach) {
  auto ring = [](double radius) {
    auto pts = std::make_shared<lista::PointSet>();
    for (int k = 0; k < 640; ++k)
      pts->xyz.emplace_back(float(radius * std::cos(0.01 * k)), float(radius * std::sin(0.01 * k)), 0.f);
    return pts;
  };
  auto mission = [&](double step, double radius, int scans) {
    lista::Mission m;
    for (int i = 0; i < scans; ++i) {
      lista::Scan s;
      s.pose.translation() = Eigen::Vector3d(step * i, 0, 0);
      s.points = ring(radius);
      m.scans.push_back(s);
    }
    return m;
  };
  EXPECT_TRUE(lista::geometry::scanned_from_stations(mission(12.0, 5.0, 3)));
  EXPECT_FALSE(lista::geometry::scanned_from_stations(mission(1.0, 5.0, 30))) << "a driving mission";
  EXPECT_TRUE(lista::geometry::scanned_from_stations(mission(0.0, 5.0, 1))) << "one scan is one station";
  lista::Mission dropout = mission(12.0, 5.0, 2);
  dropout.scans[1].points = std::make_shared<lista::PointSet>();
  EXPECT_TRUE(lista::geometry::scanned_from_stations(dropout)) << "an empty scan is stepped over";
}

TEST(OrderStatistics, KthSmallestAndTheUpperMedianWhateverTheOrder) {
  std::vector<double> v = {5, 1, 4, 2, 3, 6};
  EXPECT_EQ(lista::geometry::kth_smallest(v, 0), 1.0);
  EXPECT_EQ(lista::geometry::kth_smallest(v, 5), 6.0);
  EXPECT_EQ(lista::geometry::median(v), 4.0);  // the higher of the two middle values
  std::vector<int> odd = {9, -3, 7};
  EXPECT_EQ(lista::geometry::median(odd), 7);
  std::vector<float> one = {2.5f};
  EXPECT_EQ(lista::geometry::median(one), 2.5f);
}
