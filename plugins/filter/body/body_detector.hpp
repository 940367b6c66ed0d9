// Finds the points of a mission that belong to the robot (or the person)
// carrying the sensor: points that keep their place in the SENSOR frame
// while the sensor moves, and that other scans of the same mission, taken
// metres away, see through. The first test alone would also take the floor
// under a level robot and the walls of a corridor it walks along; those stay
// where they were seen, so the second test keeps them.
#pragma once

#include <lista/missions.hpp>

#include <cstdint>
#include <vector>

namespace lista::filter {

struct BodyConfig {
  double max_range = 1.5;         // m: body points lie nearer their sensor than this
  double cell = 0.1;              // m: sensor-frame cell size
  double min_share = 0.5;         // a body cell is occupied in at least this share of the scans
  double witness_min = 2.0;       // m: a witness scan is at least this far from the scan it checks
  double witness_max = 12.0;      // m: ... and at most this far
  double depth = 0.2;             // m: how far behind a patch a witness ray must pass to see through it
  double margin = 0.3;            // m: ... and how far beyond that point it must end
  double see_through_share = 0.5; // share of a cell's votes that must see through it
  int min_votes = 4;              // fewer votes: the cell is kept (not enough evidence)
  int min_scans = 4;              // missions with fewer scans are left as they are
  int probes = 16;                // scans (spread over the mission) whose cells are checked
  int witnesses = 4;              // witness scans per probe (nearest in scan order)
};

struct BodyCells {
  // Sensor-frame cells (geometry::voxel_key) whose points are dropped,
  // sorted: the confirmed candidates and every candidate connected to one
  // whose own votes do not say present.
  std::vector<uint64_t> drop;
  size_t candidates = 0;  // cells occupied in at least min_share of the scans
  size_t confirmed = 0;   // candidates that the witnesses saw through
  size_t voted = 0;       // candidates with at least min_votes votes
  bool checked = false;   // false: too few scans or no witnesses; nothing dropped
  size_t scans = 0;       // scans holding points
};

// The sensor-frame cell of p (cell size `cell`) as a geometry::voxel_key.
uint64_t cell_key(const Eigen::Vector3f& p, double cell);

// Scans are spread over `threads`; the result does not depend on them.
BodyCells find_body_cells(const Mission& mission, const BodyConfig& config, int threads = 1);

// Stop-and-go stations: the scans of missions too short for the witness
// test (fewer than min_scans), pooled over every such mission. What carries
// the sensor (a tripod, a robot's deck) stands at the same place in the
// sensor frame at every station, while the scene around a station differs
// from one to the next: a cell occupied in at least min_share of the station
// scans, and in at least two, is the platform; the cells beside it are not
// (why: docs/formats.md, "Stations"). Fewer than two station scans:
// nothing (`checked` false).
BodyCells find_station_body_cells(const std::vector<const PointSet*>& stations, const BodyConfig& config,
                                  int threads = 1);

// Drops from every scan of `mission` the points within max_range whose cell
// is in `cells.drop`; kept points keep their file index. Scans are spread
// over `threads`. Returns how many.
size_t drop_body_points(Mission& mission, const BodyCells& cells, const BodyConfig& config, int threads = 1);

}  // namespace lista::filter
