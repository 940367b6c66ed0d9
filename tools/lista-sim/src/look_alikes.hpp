// Shapes a LiDAR cannot tell apart. Procedural classes draw their sizes from
// continuous ranges, so among a few hundred shapes some pairs differ by a few
// millimetres (two barrels 3 mm apart in height), far below the sensors' range
// noise; a catalogue may hold one model twice. Asking a descriptor to separate
// such pairs scores noise, and training to push them apart teaches noise.
#pragma once

#include "mesh.hpp"
#include "shapes.hpp"

#include <vector>

namespace lista::sim {

// True when every point of each surface lies within `tolerance` metres of the
// other surface (symmetric Hausdorff distance <= tolerance), both meshes in
// their own frames. Checked on points sampled at most tolerance / 2 apart on
// every triangle against the exact point-triangle distance, so a bump
// narrower than that spacing may be missed; O(samples x nearby triangles).
bool surfaces_within(const TriMesh& a, const TriMesh& b, float tolerance);

// Gives look-alikes one id: in pool order, a shape takes the id of the first
// earlier shape that kept its own id and whose surface is within `tolerance`
// of its own; otherwise it keeps its id. Joining a kept shape, never a chain
// of neighbours, bounds one id's spread to 2 x tolerance. tolerance 0 merges
// nothing (identical meshes: share_ids_of_identical_geometry).
void share_ids_of_look_alikes(std::vector<Shape>& shapes, float tolerance);

}  // namespace lista::sim
