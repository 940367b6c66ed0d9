// Direct access to the volumetric.openvdb stage, for tests and the benchmark
// (pipelines load it through the plugin loader instead).
#pragma once

#include <lista/stage.hpp>

#include <memory>

namespace lista::volumetric {

StageInfo volumetric_openvdb_info();
std::unique_ptr<Stage> make_volumetric_openvdb(const Params& params);

}  // namespace lista::volumetric
