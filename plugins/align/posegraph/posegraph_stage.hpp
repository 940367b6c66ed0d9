// align.posegraph's declaration and factory, visible to its tests.
#pragma once

#include <lista/stage.hpp>

#include <memory>

namespace lista::align {

StageInfo posegraph_stage_info();
std::unique_ptr<Stage> make_posegraph_stage(const Params& params);

}  // namespace lista::align
