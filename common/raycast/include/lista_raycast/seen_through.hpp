// Dynamic evidence from the mission's other scans' beams: where a changed
// point stood, did the scans of its own mission that looked that way see it
// there, or see through its place? docs/volumetric.md, "Dynamics".
#pragma once

#include <lista/missions.hpp>
#include <lista/points.hpp>
#include <lista_raycast/volumetric_config.hpp>

namespace lista::raycast {

// Marks seen_free_in_own_mission on the changed points `changes` of
// `mission` (common frame, with their scan provenance and
// changed_against bits) whose place the mission's scans saw through at
// least as often as they saw something there, and at least once. Points are
// judged by cells of two voxels (lista_geometry/range_image.hpp's look,
// each scan's beams within a cell of the point); a beam that ended short
// of the place (an occlusion) or none that came near gives no vote. A
// walker seen by one scan and gone when the next looked is caught though no
// beam crossed its voxels themselves, which a sparse scanner's rings rarely
// do. Missions scanned from stations (lista_geometry/stations.hpp, one
// scan included) are left as they are: a few looks from far apart, where
// stations placed a few centimetres off see through each other's objects.
// Deterministic for any thread count.
void mark_seen_through(const Mission& mission, PointSet& changes, const VolumetricConfig& config, int threads);

}  // namespace lista::raycast
