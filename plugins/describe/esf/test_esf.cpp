#include <lista_objfeat/plugin_testing.hpp>

#include <chrono>
#include <gtest/gtest.h>
#include <thread>

using namespace lista::objfeat::testing;

TEST(DescribeEsf, OneUnitRowPerObjectAndViewsOfOneShapeAreCloser) {
  auto stage = make_stage();
  lista::ObjectSet set = two_views_each(5, 21);
  auto d = describe(*stage, set);
  ASSERT_EQ(d.values.rows(), 10);
  ASSERT_EQ(d.dim(), 640);
  for (long i = 0; i < d.values.rows(); ++i) EXPECT_NEAR(d.values.row(i).norm(), 1.f, 1e-4f);
  auto [within, between] = within_between(d);
  EXPECT_LT(within, between);
}

TEST(DescribeEsf, DeterministicAcrossCallsAndSeconds) {
  auto stage = make_stage();
  lista::ObjectSet set = two_views_each(1, 3);
  auto a = describe(*stage, set);
  // PCL seeds its sampler from the wall clock (seconds): cross a second
  // boundary, so a clock-seeded build would give a different row.
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  auto b = describe(*stage, set);
  EXPECT_EQ((a.values - b.values).cwiseAbs().maxCoeff(), 0.f);
}

TEST(DescribeEsf, EmptyObjectIsAnError) {
  auto stage = make_stage();
  lista::ObjectSet set;
  set.objects.push_back(object_from(0, {}));
  EXPECT_THROW(describe(*stage, set), lista::Error);
}
