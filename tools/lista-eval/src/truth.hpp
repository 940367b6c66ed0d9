// The truth a run is scored against: ground_truth.json plus every point's
// label, indexed the way change clouds name points (scan, index in file).
#pragma once

#include <lista/missions.hpp>
#include <lista_io/report.hpp>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace lista::eval {

// Poses more than this far apart mean the object moved (data contract, sect. 3).
constexpr double kMovedMeters = 0.05;
constexpr double kMovedDegrees = 5.0;
constexpr uint32_t kNoPoint = 0xffffffffu;  // label slot of a non-finite point
constexpr double kSwapMeters = 0.4;         // how near two swapped objects stand to each other's place

struct MissionTruth {
  std::string name;
  // labels[scan][index]: the point's label, kNoPoint for a non-finite point.
  std::vector<std::vector<uint32_t>> labels;
  std::map<uint32_t, size_t> points_per_label;
};

struct Truth {
  std::string dataset;
  io::GroundTruth gt;
  MissionSet missions;               // the compared missions, points loaded
  std::vector<MissionTruth> labels;  // same order as missions
  std::set<uint32_t> dynamic;        // ids whose points are left out of every score
  std::set<uint32_t> changed;        // ids added, removed or moved between the compared missions
  // accepted[id][mission]: the statuses a report may give a changed object
  // present there. With 3+ missions an object can change against both
  // neighbours (moved from B to C, then removed in D: in C it is moved and
  // removed), and a report gives one status, so either is right. From the
  // neighbouring missions: gone in the next one = removed, absent in the
  // previous one = added, posed differently in either = moved. An object
  // that changed only between missions further apart gets the status of
  // the whole sequence (removed over added over moved).
  std::map<uint32_t, std::map<std::string, std::set<std::string>>> accepted;
  // status[id][mission]: the one status shown for it (the first accepted of
  // moved, removed, added).
  std::map<uint32_t, std::map<std::string, std::string>> status;
  // Moved objects that exchanged places with another object of their class
  // between two compared missions (each stands, within kSwapMeters, where
  // the other stood): by mission name, the ids. Two identical objects
  // swapped leave the occupancy as it was, so no volumetric method sees
  // them; lista-eval says how much of a score they take.
  std::map<std::string, std::set<uint32_t>> swapped;

  const io::TruthObject* object(uint32_t id) const;
  size_t mission_index(const std::string& name) const;  // throws if not compared
};

// True if two world poses are more than 5 cm or 5 degrees apart.
bool poses_differ(const Eigen::Matrix4d& a, const Eigen::Matrix4d& b);

// Reads ground_truth.json and the compared missions' points. `missions`
// empty = the ground truth's missions. Errors: no ground truth, unknown
// mission, no per-point labels.
Truth load_truth(const std::string& dataset, const std::vector<std::string>& missions, int threads);

}  // namespace lista::eval
