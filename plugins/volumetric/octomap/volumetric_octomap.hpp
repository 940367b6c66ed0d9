// Direct access to the volumetric.octomap stage, for tests and the benchmark
// (pipelines load it through the plugin loader instead).
#pragma once

#include <lista/stage.hpp>

#include <memory>

namespace lista::volumetric {

StageInfo volumetric_octomap_info();
std::unique_ptr<Stage> make_volumetric_octomap(const Params& params);

}  // namespace lista::volumetric
