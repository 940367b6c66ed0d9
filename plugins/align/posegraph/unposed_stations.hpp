// Missions whose poses.txt puts every scan at one place (a terrestrial
// scanner's stations often come without poses): their own poses cannot say
// where the stations stood, so each station is aligned as a mission of its
// own (Scan Context, the whole-map search, closures) and the stations are
// joined back into their mission afterwards.
#pragma once

#include <lista/missions.hpp>

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace lista::align {

inline constexpr size_t kWholeMission = static_cast<size_t>(-1);

struct StationSplit {
  MissionSet set;  // the missions to align: unposed missions cut into one-scan missions
  // Per mission of `set`: the original mission and, for a cut-out station,
  // its scan (kWholeMission: the whole mission, kept as it was).
  std::vector<std::pair<size_t, size_t>> from;
  std::vector<std::string> split;  // names of the missions cut into stations
};

// Every scan's pose within 1 cm of the first's.
bool at_one_place(const Mission& mission);

StationSplit split_unposed_stations(const MissionSet& missions);

// The original missions, each placed as its parts were aligned: a cut
// mission's frame is its first station's, its scan poses the stations'
// placements in it.
MissionSet join_stations(const MissionSet& original, const StationSplit& split, const MissionSet& aligned);

// One warning per cut mission some of whose stations the final closures
// do not link to the first mission (`linked`, per mission of split.set):
// those were placed by no registration and stand nowhere in particular.
std::vector<std::string> unplaced_stations_warnings(const MissionSet& original, const StationSplit& split,
                                                    const std::vector<char>& linked);

}  // namespace lista::align
