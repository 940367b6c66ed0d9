// Test helpers shared by both volumetric plugins' suites: what each must
// declare of the shared parameters (raycast::volumetric_params), and that
// it passes them on to its ray casting.
#pragma once

#include <lista/stage.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
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

// graze_height reaches the backend's ray casting: the synthetic scene's
// floor beams, going down, lose free space before their returns.
// `free_voxels(params)` runs the backend and returns mission A's free voxels.
inline void expect_graze_height_shortens_floor_beams(const Params& defaults,
                                                     const std::function<double(const Params&)>& free_voxels) {
  Params grazing = defaults;
  grazing.set("graze_height", 0.1);
  grazing.set("graze_max", 2.0);
  const double off = free_voxels(defaults), on = free_voxels(grazing);
  EXPECT_GT(off, 0.0);
  EXPECT_LT(on, 0.95 * off) << "graze_height did not shorten any beam";
}

}  // namespace lista::volumetric::testing
