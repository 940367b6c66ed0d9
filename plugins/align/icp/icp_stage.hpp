// align.icp's declaration and factory, visible to its tests.
#pragma once

#include <lista/stage.hpp>

#include <memory>

namespace lista::align {

StageInfo icp_stage_info();
std::unique_ptr<Stage> make_icp_stage(const Params& params);

}  // namespace lista::align
