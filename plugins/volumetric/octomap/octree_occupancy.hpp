// Occupancy mapping with OctoMap: one OcTree per mission, filled the way
// OcTree::insertPointCloud does it but with the per-beam key rays computed on
// several threads. Only this file and its .cpp include OctoMap.
#pragma once

#include <lista/missions.hpp>
#include <lista_raycast/change_detection.hpp>

#include <memory>

namespace lista::volumetric {

std::unique_ptr<raycast::OccupancyMap> build_octree_map(const Mission& mission,
                                                        const raycast::VolumetricConfig& config,
                                                        int threads, raycast::MapStats& stats,
                                                        Progress* progress = nullptr);

}  // namespace lista::volumetric
