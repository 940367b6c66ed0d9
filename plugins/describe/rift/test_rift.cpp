#include <lista_objfeat/plugin_testing.hpp>

#include <gtest/gtest.h>

using namespace lista::objfeat::testing;

TEST(DescribeRift, OneUnitRowPerObjectAndViewsOfOneShapeAreCloser) {
  auto stage = make_stage();
  lista::ObjectSet set = two_views_each(4, 21, true);
  auto d = describe(*stage, set, 2);
  ASSERT_EQ(d.values.rows(), 8);
  ASSERT_EQ(d.dim(), 32);
  EXPECT_EQ(d.object_ids[5], 5);
  for (long i = 0; i < d.values.rows(); ++i) EXPECT_NEAR(d.values.row(i).norm(), 1.f, 1e-4f);
  auto [within, between] = within_between(d);
  EXPECT_LT(within, between);
}

TEST(DescribeRift, BadInputIsAnError) {
  EXPECT_THROW(make_stage({{"voxel", 0.3}, {"support_radius", 0.2}}), lista::Error);
  auto stage = make_stage();
  lista::ObjectSet set;
  set.objects.push_back(object_from(0, {}));
  EXPECT_THROW(describe(*stage, set), lista::Error);
}

TEST(DescribeRift, WorksWithoutIntensity) {
  auto stage = make_stage();
  lista::ObjectSet set = two_views_each(2, 4, false);
  auto d = describe(*stage, set);
  ASSERT_EQ(d.values.rows(), 4);
  EXPECT_TRUE(d.values.allFinite());
}
