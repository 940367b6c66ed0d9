// Scans io.missions did not read (scan_spacing thins a dense log) keep their
// pose but hold no points; their points still belong in changes/ (data
// contract, sect. 2: a pipeline that downsamples reports original points).
// Each such scan is read here, placed by its pose as the run aligned it, and
// every point that falls in a cell of the mission's change takes that
// cell's object.
#pragma once

#include "report_build.hpp"

namespace lista::io {

struct UnreadScans {
  size_t scans = 0;   // scans read here
  size_t points = 0;  // of their points, those added to changes/
};

// Adds to b.clouds (MissionSet order) the points of every scan with no points
// and points_in_file 0 that lie in a `cell`-sized cube holding a change row
// of the same mission. Scans are read on `threads`; rows come out in scan
// order, so the result does not depend on them.
UnreadScans add_unread_scans(const MissionSet& missions, Built& b, double cell, int threads);

}  // namespace lista::io
