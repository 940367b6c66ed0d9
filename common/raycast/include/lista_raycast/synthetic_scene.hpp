// A small synthetic LiDAR scene for tests and the benchmark's --synthetic
// mode: two rooms split by a full wall, a few boxes, a spinning multi-beam
// sensor ray-cast analytically. Mission "A" scans both rooms; mission "B"
// scans only room 1 (room 2 is never observed in B). Between A and B:
//   label 1  box in room 1, removed (present in A only)
//   label 2  box in room 2, removed, but room 2 is unobserved in B
//   label 3  box in room 1, added (present in B only)
//   label 4  static box in room 1 (both missions)
// Mission B's map frame is offset from the common frame (to_common is set to
// the truth) so frame handling is exercised.
#pragma once

#include <lista/missions.hpp>

#include <cstdint>

namespace lista::raycast {

struct SyntheticSceneConfig {
  int rings = 32;             // beams per column, elevation -45..+45 deg
  int columns = 512;          // azimuth steps per revolution
  int scans_per_position = 1; // repeated scans per sensor position (slightly jittered)
  double range_noise = 0.005; // m, Gaussian sigma
  double scale = 1.0;         // multiplies the room size (bigger = longer rays)
  uint64_t seed = 1;
};

MissionSet make_synthetic_scene(const SyntheticSceneConfig& config = {});

}  // namespace lista::raycast
