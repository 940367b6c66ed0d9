#include "unposed_stations.hpp"

#include <string>

namespace lista::align {

bool at_one_place(const Mission& mission) {
  for (const Scan& s : mission.scans)
    if ((s.pose.translation() - mission.scans.front().pose.translation()).norm() > 0.01) return false;
  return true;
}

StationSplit split_unposed_stations(const MissionSet& missions) {
  StationSplit out;
  out.set.dataset = missions.dataset;
  out.set.origin = missions.origin;
  for (size_t m = 0; m < missions.missions.size(); ++m) {
    const Mission& mission = missions.missions[m];
    if (mission.scans.size() < 2 || !at_one_place(mission)) {
      out.set.missions.push_back(mission);
      out.from.push_back({m, kWholeMission});
      continue;
    }
    out.split.push_back(mission.name);
    for (size_t s = 0; s < mission.scans.size(); ++s) {
      // An empty scan (a dropout) has nothing to place: it keeps its pose.
      if (!mission.scans[s].points || mission.scans[s].points->empty()) continue;
      Mission station;
      station.name = mission.name + "/station " + std::to_string(s + 1);
      station.dir = mission.dir;
      station.scans = {mission.scans[s]};
      station.to_common = mission.to_common;
      if (s < mission.poses_gt.size()) station.poses_gt = {mission.poses_gt[s]};
      out.set.missions.push_back(std::move(station));
      out.from.push_back({m, s});
    }
  }
  return out;
}

MissionSet join_stations(const MissionSet& original, const StationSplit& split, const MissionSet& aligned) {
  MissionSet out = original;
  std::vector<char> framed(original.missions.size(), 0);
  for (size_t k = 0; k < split.from.size(); ++k) {
    const auto [m, s] = split.from[k];
    const Mission& part = aligned.missions[k];
    Mission& mission = out.missions[m];
    if (s == kWholeMission) {
      mission.to_common = part.to_common;
      mission.scans = part.scans;
      continue;
    }
    if (!framed[m]) mission.to_common = part.to_common, framed[m] = 1;  // the first station's frame
    mission.scans[s].pose = mission.to_common.inverse() * part.sensor_to_common(0);
  }
  return out;
}

std::vector<std::string> unplaced_stations_warnings(const MissionSet& original, const StationSplit& split,
                                                    const std::vector<char>& linked) {
  std::vector<size_t> unplaced(original.missions.size(), 0), stations(original.missions.size(), 0);
  for (size_t k = 0; k < split.from.size(); ++k) {
    const auto [m, s] = split.from[k];
    if (s == kWholeMission) continue;
    ++stations[m];
    if (k >= linked.size() || !linked[k]) ++unplaced[m];
  }
  std::vector<std::string> out;
  for (size_t m = 0; m < original.missions.size(); ++m)
    if (unplaced[m] > 0)
      out.push_back("mission '" + original.missions[m].name + "' (stations without poses): " +
                    std::to_string(unplaced[m]) + " of its " + std::to_string(stations[m]) +
                    " stations could not be placed by registering them with the others, so the mission's map and "
                    "its changes are wrong; give registered station poses in poses.txt");
  return out;
}

}  // namespace lista::align
