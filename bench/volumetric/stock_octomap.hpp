// The baseline: OctoMap used the way the paper did, one
// OcTree::insertPointCloud per scan with the scan's sensor origin.
#pragma once

#include <lista/missions.hpp>
#include <lista_raycast/volumetric_config.hpp>

#include <cstdint>
#include <functional>

struct StockResult {
  size_t scans = 0;
  uint64_t rays = 0, voxel_visits = 0;  // visits counted with the same DDA, outside the timing
  double seconds = 0;
  size_t leaf_nodes = 0;
};

// Inserts the first `max_scans` scans (0 = all) of one mission; `progress`
// (if set) hears (scans done, scans to do) after each scan.
StockResult run_stock_octomap(const lista::Mission& mission, const lista::raycast::VolumetricConfig& c,
                              size_t max_scans, const std::function<void(size_t, size_t)>& progress = {});
