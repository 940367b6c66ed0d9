// The perfect run of a dataset, written from its ground truth: what an ideal
// pipeline would report (used to check the scorer and as a reference).
#pragma once

#include "truth.hpp"

#include <string>

namespace lista::eval {

// Writes <out>/changes/<mission>.pcd (every point of a truly changed object)
// and <out>/report.json (one object per changed object and mission it is seen
// in; common frame = world, alignment = mission_to_world; group = index of the
// class name; moved objects matched to their next appearance, else previous).
// report.json is written last, after the old one is removed.
void write_perfect_run(const Truth& truth, const std::string& out_dir);

}  // namespace lista::eval
