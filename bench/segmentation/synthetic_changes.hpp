// A synthetic change cloud of realistic size and make-up for timing the
// segmentation stage: object surfaces (boxes and balls, 0.2-1.5 m) sampled at
// LiDAR-like spacing with range noise, floor patches where objects left, and
// scattered sensor noise. Deterministic from the seed.
#pragma once

#include <lista/points.hpp>

#include <cstdint>

namespace lista::bench {

struct SyntheticChangeConfig {
  int objects = 60;            // per mission
  double spacing = 0.015;      // m, surface sample spacing
  double noise_fraction = 0.03;  // scattered noise points / object points
  double extent = 40.0;        // m, square area the objects are spread over
  uint64_t seed = 1;
};

// `truth` gets, per point, the object it belongs to (0 = floor or noise).
PointSet synthetic_changes(const SyntheticChangeConfig& config, std::vector<uint32_t>* truth = nullptr);

}  // namespace lista::bench
