#include <lista_objfeat/canonical.hpp>
#include <lista_objfeat/retrieval.hpp>
#include <lista_objfeat/sha256.hpp>
#include <lista_objfeat/synthetic.hpp>

#include <lista/error.hpp>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

using namespace lista::objfeat;

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

TEST(Canonical, FewPointsAreRepeatedAndEmptyIsAnError) {
  std::vector<Eigen::Vector3f> three = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}};
  CanonicalCloud c = make_canonical(three, {});
  EXPECT_EQ(c.points, 256);
  EXPECT_THROW(make_canonical(std::vector<Eigen::Vector3f>{}, CanonicalConfig{}), lista::Error);
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
  EXPECT_EQ(lone.top1_hits, (std::vector<int>{1, 1, 1, 1, 0, 0}));
  EXPECT_EQ(lone.queries, 4);
  EXPECT_THROW(score_retrieval(x, {1, 2}), lista::Error);
}
