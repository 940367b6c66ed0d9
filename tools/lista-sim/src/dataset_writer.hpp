// Renders a planned scenario into a dataset in the layout of the data
// contract, sect. 1, plus ground_truth.json (sect. 3).
#pragma once

#include "bag_writer.hpp"
#include "scenario.hpp"
#include "sensor.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lista::sim {

struct WriteOptions {
  std::string out;        // dataset folder
  uint64_t seed = 0;
  int threads = 1;
  bool overwrite = false; // replace the mission folders and ground truth already there
  bool progress = false;  // progress lines on stderr
  bool body = false;      // a robot's back in every scan (SweepOptions::body)
  bool mixed_pixels = false, dark_dropouts = false;  // SweepOptions' sensor effects
  // Missions as the data contract's folders (none), or as recorded bags.
  std::optional<BagFormat> bag;
  // Sweeps take 0.1 s while the sensor moves on to the next scan's pose
  // (SweepOptions::sweep_end): skewed scans; bags carry each point's time.
  bool skew = false;
};

struct WriteStats {
  std::vector<size_t> points_per_mission;
  std::vector<size_t> scans_per_mission;
  double seconds = 0.0;
};

WriteStats write_dataset(const Scenario& scenario, const SensorModel& sensor, const WriteOptions& options);

}  // namespace lista::sim
