// Test helper shared by both volumetric plugins' suites: what each must
// declare of the shared parameters (raycast::volumetric_params).
#pragma once

#include <lista/stage.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace lista::volumetric::testing {

// max_range had no range, so NaN passed validation and ran as "unlimited".
inline void expect_max_range_finite_and_not_negative(const StageInfo& info) {
  const ParamSpec* max_range = info.param("max_range");
  ASSERT_NE(max_range, nullptr);
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), -1.0})
    EXPECT_NE(max_range->check(bad), "") << bad;
  EXPECT_EQ(max_range->check(0.0), "");  // 0: unlimited
  EXPECT_EQ(max_range->check(30.0), "");
  EXPECT_EQ(info.declaration_problem(), "");
}

}  // namespace lista::volumetric::testing
