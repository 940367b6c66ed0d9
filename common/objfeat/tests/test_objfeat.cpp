#include <lista_geometry/bounding_rectangle.hpp>
#include <lista_objfeat/canonical.hpp>
#include <lista_objfeat/retrieval.hpp>
#include <lista_objfeat/sha256.hpp>
#include <lista_objfeat/synthetic.hpp>

#include <lista/error.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <random>

using namespace lista::objfeat;
using lista::geometry::BoundingRectangle;
using lista::geometry::min_perimeter_rectangle;

TEST(Sha256, KnownVectors) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex(std::string(1000, 'a')).substr(0, 16), "41edece42d63e8d9");
}

TEST(Canonical, FixedSizeAndYawInvariant) {
  std::mt19937_64 rng(3);
  Shape shape = random_shape(rng);
  auto view = render_view(shape, 0.f, {0.f, 0.f}, rng);
  CanonicalConfig cfg;
  cfg.points = 128;
  CanonicalCloud a = make_canonical(view, cfg);
  ASSERT_EQ(a.features.size(), size_t(128 * kCanonicalChannels));

  Eigen::Matrix3f r = Eigen::AngleAxisf(1.1f, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3f> turned;
  for (const auto& p : view) turned.push_back(r * p + Eigen::Vector3f(5.f, -2.f, 0.f));
  CanonicalCloud b = make_canonical(turned, cfg);
  float max_diff = 0.f;
  for (size_t i = 0; i < a.features.size(); ++i) max_diff = std::max(max_diff, std::abs(a.features[i] - b.features[i]));
  EXPECT_LT(max_diff, 1e-3f);
}

// Points on the outline of a w x d box footprint turned by `yaw`; `faces`
// picks which sides a scan sees (bit 0: +x, 1: +y, 2: -x, 3: -y), so a
// partial view is an L or a single face.
std::vector<Eigen::Vector3f> box_faces(float w, float d, float h, float yaw, int faces) {
  std::vector<Eigen::Vector3f> out;
  Eigen::Matrix3f r = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  for (float z = 0.f; z <= h; z += 0.05f)
    for (float t = -0.5f; t <= 0.5f; t += 0.01f) {
      if (faces & 1) out.push_back(r * Eigen::Vector3f(w / 2, t * d, z));
      if (faces & 2) out.push_back(r * Eigen::Vector3f(t * w, d / 2, z));
      if (faces & 4) out.push_back(r * Eigen::Vector3f(-w / 2, t * d, z));
      if (faces & 8) out.push_back(r * Eigen::Vector3f(t * w, -d / 2, z));
    }
  return out;
}

TEST(BoundingRectangle, FindsTheBoxSidesOfFullAndPartialViews) {
  for (float yaw : {0.f, 0.4f, 1.3f, -2.5f}) {
    const Eigen::Vector2d along(std::cos(yaw), std::sin(yaw));
    // Whole outline, and an L of a long and a short face: the principal axis
    // of the L leans towards its diagonal, the rectangle does not.
    for (int faces : {15, 3}) {
      BoundingRectangle r = min_perimeter_rectangle(box_faces(1.2f, 0.5f, 0.8f, yaw, faces));
      ASSERT_TRUE(r.valid);
      EXPECT_NEAR(std::abs(r.long_axis.dot(along)), 1.0, 1e-6) << "yaw " << yaw << " faces " << faces;
      EXPECT_NEAR(r.long_side, 1.2, 0.011);
      EXPECT_NEAR(r.short_side, 0.5, 0.011);
    }
  }
  // A random blob against a fine search over all orientations.
  std::mt19937_64 rng(11);
  std::normal_distribution<float> g(0.f, 1.f);
  std::vector<Eigen::Vector3f> blob;
  for (int i = 0; i < 5000; ++i) blob.emplace_back(1.5f * g(rng), 0.6f * g(rng) + 0.3f * std::abs(g(rng)), g(rng));
  double searched = INFINITY;
  for (double a = 0.0; a < M_PI / 2; a += 1e-4) {
    const Eigen::Vector2d u(std::cos(a), std::sin(a)), v(-u.y(), u.x());
    double lu = INFINITY, hu = -INFINITY, lv = INFINITY, hv = -INFINITY;
    for (const auto& p : blob) {
      const Eigen::Vector2d q(p.x(), p.y());
      lu = std::min(lu, q.dot(u)), hu = std::max(hu, q.dot(u)), lv = std::min(lv, q.dot(v)), hv = std::max(hv, q.dot(v));
    }
    searched = std::min(searched, hu - lu + hv - lv);
  }
  BoundingRectangle r = min_perimeter_rectangle(blob);
  EXPECT_LE(r.long_side + r.short_side, searched + 1e-9);
  EXPECT_GT(r.long_side + r.short_side, searched - 1e-3);
  // A single vertical line or wall seen edge-on spans no area.
  EXPECT_FALSE(min_perimeter_rectangle({{0, 0, 0}, {1, 1, 0}, {2, 2, 1}}).valid);
  EXPECT_FALSE(min_perimeter_rectangle({}).valid);
}

TEST(Canonical, RectangleFrameLinesUpWithFacesAndMeasuresExtents) {
  // The L of two faces (1.2 m and 0.5 m long, 0.8 m high): in the rectangle
  // frame the globals are the box's extents, whatever the yaw.
  for (float yaw : {0.3f, 2.0f}) {
    CanonicalCloud c = make_canonical(box_faces(1.2f, 0.5f, 0.8f, yaw, 3), {});
    EXPECT_NEAR(c.globals[0], 1.2f, 0.011f);
    EXPECT_NEAR(c.globals[1], 0.5f, 0.011f);
    EXPECT_NEAR(c.globals[2], 0.8f, 0.051f);
    EXPECT_GT(c.globals[3], 0.f);  // centroid above the lowest point
    EXPECT_LT(c.globals[3], c.globals[2]);
    // The principal-axis frame of the same L is turned off the faces, so its
    // footprint extents are not the box's.
    CanonicalConfig first;
    first.frame = YawFrame::principal_axis;
    CanonicalCloud p = make_canonical(box_faces(1.2f, 0.5f, 0.8f, yaw, 3), first);
    EXPECT_GT(std::abs(p.globals[0] - 1.2f) + std::abs(p.globals[1] - 0.5f), 0.05f);
  }
}

// The half of a barrel a sensor sees (radius 0.3 m, 0.9 m high, 1 cm noise):
// the fitted footprint circle gives its radius, although the extent across
// the line of sight is only a diameter and along it only a radius.
TEST(Canonical, FootprintCircleMeasuresARoundObjectFromOneSide) {
  std::mt19937_64 rng(11);
  std::normal_distribution<float> noise(0.f, 0.01f);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  std::vector<Eigen::Vector3f> half;
  for (int i = 0; i < 3000; ++i) {
    const float a = 3.1416f * u(rng), z = 0.9f * u(rng);
    half.emplace_back(0.3f * std::cos(a) + noise(rng), 0.3f * std::sin(a) + noise(rng), z);
  }
  for (float yaw : {0.f, 1.3f}) {
    const Eigen::Matrix3f r = Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitZ()).toRotationMatrix();
    std::vector<Eigen::Vector3f> turned;
    for (const auto& p : half) turned.push_back(r * p);
    const CanonicalCloud c = make_canonical(turned, {});
    EXPECT_NEAR(c.globals[4], 0.3f, 0.015f) << "yaw " << yaw;
    EXPECT_LT(c.globals[5], 0.02f);  // the residual is about the noise
  }
  // An L of two flat faces fits a circle badly: a residual far above the
  // barrel's, a radius no larger than the cap (twice the horizontal extent).
  const CanonicalCloud box = make_canonical(box_faces(1.2f, 0.5f, 0.8f, 0.4f, 3), {});
  EXPECT_GT(box.globals[5], 0.05f);
  EXPECT_LE(box.globals[4], 2.f * 1.2f + 0.03f);
  // A single flat face fits no circle at all: the radius is the cap.
  const CanonicalCloud face = make_canonical(box_faces(1.2f, 0.5f, 0.8f, 0.4f, 1), {});
  EXPECT_NEAR(face.globals[4], 2.f * std::max(face.globals[0], face.globals[1]), 1e-4f);
}

// One stray point stretches max - min, not the cells' percentile spreads.
TEST(Canonical, RobustSpreadsIgnoreAStrayPoint) {
  auto faces = box_faces(1.2f, 0.5f, 0.8f, 0.f, 3);
  const CanonicalCloud clean = make_canonical(faces, {});
  faces.emplace_back(0.f, 0.f, 2.0f);  // 1.2 m above the top
  const CanonicalCloud stray = make_canonical(faces, {});
  EXPECT_GT(stray.globals[2], clean.globals[2] + 1.f);
  for (int g = 6; g < 9; ++g) {
    EXPECT_NEAR(stray.globals[size_t(g)], clean.globals[size_t(g)], 0.1f) << "global " << g;
    EXPECT_GT(clean.globals[size_t(g)], 0.f);
  }
  EXPECT_NEAR(clean.globals[8], 0.8f, 0.1f);
}

TEST(Canonical, FewPointsAreRepeatedAndEmptyIsAnError) {
  std::vector<Eigen::Vector3f> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}};
  CanonicalCloud c = make_canonical(three, {});
  EXPECT_EQ(c.points, 256);
  EXPECT_THROW(make_canonical(std::vector<Eigen::Vector3f>{}, CanonicalConfig{}), lista::Error);
}

// Several selections share the frame and cells: element k is exactly the
// single cloud made with seed + k.
TEST(Canonical, SamplesAreTheSingleCloudsOfTheirSeeds) {
  std::vector<Eigen::Vector3f> pts = box_faces(1.2f, 0.5f, 0.8f, 0.4f, 3);
  CanonicalConfig cfg;
  cfg.points = 64;
  const auto many = make_canonical_samples(pts, cfg, 3);
  ASSERT_EQ(many.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    CanonicalConfig one = cfg;
    one.seed = cfg.seed + uint64_t(k);
    const CanonicalCloud c = make_canonical(pts, one);
    EXPECT_EQ(many[size_t(k)].features, c.features) << k;
    EXPECT_EQ(many[size_t(k)].globals, c.globals) << k;
  }
  EXPECT_NE(many[0].features, many[1].features);
  EXPECT_THROW(make_canonical_samples(pts, cfg, 0), lista::Error);
}

TEST(Retrieval, PerfectAndShuffledLabels) {
  Rows x(6, 2);
  x << 0, 0, 0.1f, 0, 5, 5, 5.1f, 5, 10, 0, 10.1f, 0;
  RetrievalScores s = score_retrieval(x, {1, 1, 2, 2, 3, 3});
  EXPECT_DOUBLE_EQ(s.top1, 1.0);
  EXPECT_DOUBLE_EQ(s.map, 1.0);
  EXPECT_DOUBLE_EQ(s.purity, 1.0);
  EXPECT_EQ(s.top1_hits, std::vector<int>(6, 1));
  RetrievalScores bad = score_retrieval(x, {1, 2, 3, 1, 2, 3});
  EXPECT_LT(bad.top1, 0.5);
  EXPECT_EQ(bad.top1_hits, std::vector<int>(6, 0));  // every nearest row has another label
  // A row whose label occurs once is no query and never a hit.
  RetrievalScores lone = score_retrieval(x, {1, 1, 2, 2, 3, 4});
  EXPECT_EQ(lone.top1_hits, (std::vector<int>{1, 1, 1, 1, -1, -1}));
  EXPECT_EQ(lone.queries, 4);
  EXPECT_THROW(score_retrieval(x, {1, 2}), lista::Error);
}

// A constant descriptor ties every row: each query gets the share of the
// others with its label (chance), not the label of whichever row comes first.
TEST(Retrieval, TiesCountByTheirShare) {
  Rows x = Rows::Ones(6, 3);
  const std::vector<int> labels = {1, 1, 2, 2, 2, 3};
  // Queries: the 1s (1 of 5 others shares the label) and the 2s (2 of 5).
  const double chance = (2 * 1.0 / 5 + 3 * 2.0 / 5) / 5;
  EXPECT_NEAR(score_retrieval(x, labels).top1, chance, 1e-12);  // row order alone gave 0.4
}

// A view that misses the bottom 0.3 m of a 0.8 m box (a sensor close above
// it): from the floor, heights are the box's own; from the lowest point they
// are 0.3 m short, and the gap global says how much was missed.
TEST(Canonical, HeightsFromTheFloorWhenItIsKnownAndUsed) {
  std::vector<Eigen::Vector3f> cut;
  for (const auto& p : box_faces(1.2f, 0.5f, 0.8f, 0.4f, 3))
    if (p.z() >= 0.3f - 1e-4f) cut.push_back(p + Eigen::Vector3f(0.f, 0.f, 2.f));  // floor at z = 2
  CanonicalConfig with_floor;
  with_floor.floor = true;
  const CanonicalCloud lowest = make_canonical(cut, with_floor);  // floor unknown
  const CanonicalCloud floor = make_canonical(cut, with_floor, 2.f);
  EXPECT_NEAR(floor.globals[9], 0.3f, 1e-3f);
  EXPECT_NEAR(floor.globals[3] - lowest.globals[3], 0.3f, 1e-3f);
  EXPECT_EQ(lowest.globals[9], 0.f);
  for (int i = 0; i < floor.points; ++i) {
    const float from_floor = floor.features[size_t(i) * kCanonicalChannels + 5];
    EXPECT_NEAR(from_floor - lowest.features[size_t(i) * kCanonicalChannels + 5], 0.3f, 1e-3f);
    EXPECT_GE(from_floor, 0.3f - 1e-3f);
    EXPECT_LE(from_floor, 0.8f + 1e-3f);
  }
  // A configuration without the floor (the models before it) ignores it.
  const CanonicalCloud ignored = make_canonical(cut, CanonicalConfig{}, 2.f);
  const CanonicalCloud plain = make_canonical(cut, CanonicalConfig{});
  EXPECT_EQ(ignored.features, plain.features);
  EXPECT_EQ(ignored.globals, plain.globals);
  EXPECT_EQ(plain.features, lowest.features);
  // A floor estimate above the lowest point is clamped to it: no negative heights.
  const CanonicalCloud high = make_canonical(cut, with_floor, 2.5f);
  EXPECT_EQ(high.globals, lowest.globals);
  // Yaw about z still changes nothing.
  const Eigen::Matrix3f r = Eigen::AngleAxisf(2.2f, Eigen::Vector3f::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3f> turned;
  for (const auto& p : cut) turned.push_back(r * p);
  const CanonicalCloud t = make_canonical(turned, with_floor, 2.f);
  for (size_t g = 0; g < floor.globals.size(); ++g) EXPECT_NEAR(t.globals[g], floor.globals[g], 1e-3f) << g;
}
