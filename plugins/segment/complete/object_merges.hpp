// Rules that join objects of one mission: fragments nested in a larger
// object's box (rule 6) and objects the mission's cloud connects over
// changed points (rule 4b). Internal to segment.complete.
#pragma once

#include "local_cloud.hpp"

#include <lista/objects.hpp>

#include <string>
#include <tuple>
#include <vector>

namespace lista::segment::completion {

// Removes the objects marked in `gone` (aligned with set.objects) and
// renumbers the rest 0..n-1 in order.
void drop_objects(ObjectSet& set, const std::vector<char>& gone);

// Rule 6: an object whose points lie mostly (`share`) inside the box of a
// larger object of the same mission (grown by half a voxel) is a fragment of
// it: growth stops at points another object owns, so two clusters of one
// object stay two, interleaved in the same box. Smallest first, so a chain of
// fragments ends in the largest. Returns how many objects were absorbed.
size_t absorb_nested(ObjectSet& set, double share, float margin);

// Rule 4b: joins the objects of one mission that its cloud connects over
// changed points. `candidates`: (gap, i, j) same-mission pairs of free
// objects, nearest first. Growth from i inside the union of the two boxes
// grown by box_margin (down to the floor) must reach j over points it
// adds, and at most 1 - static_share of those may lie where every
// neighbouring mission holds points too: the material between them changed
// with them (a table's top between the legs the difference found). Objects
// whose voxels touch are left apart: segment.carve and segment.overlap cut
// them so on purpose. Each component joins its largest member; returns how
// many objects joined another (ids renumbered when any did).
size_t join_connected(ObjectSet& set, const std::vector<std::tuple<float, size_t, size_t>>& candidates,
                      const std::vector<LocalCloud>& clouds, const std::vector<std::vector<size_t>>& neighbours,
                      const CompletionConfig& c, std::vector<std::string>& notes);

}  // namespace lista::segment::completion
