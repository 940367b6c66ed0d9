// Occupancy mapping with OpenVDB: one log-odds FloatGrid per mission, built
// for throughput. Only this file and its .cpp include OpenVDB.
#pragma once

#include <lista/missions.hpp>
#include <lista_raycast/change_detection.hpp>

#include <memory>

namespace lista::volumetric {

// A mission's map; the grid stays hidden behind the OccupancyMap interface.
std::unique_ptr<raycast::OccupancyMap> build_vdb_map(const Mission& mission,
                                                     const raycast::VolumetricConfig& config,
                                                     int threads, raycast::MapStats& stats,
                                                     Progress* progress = nullptr);

}  // namespace lista::volumetric
