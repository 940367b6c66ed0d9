// What the scans of one mission saw where another mission's truly changed
// points lie, asked at the true poses (poses_gt.txt): a ray through the
// point that ends beyond it (the place seen empty, so the change can show),
// a return at the point (something there), or neither (occluded, out of
// range or between the beams). The share seen empty bounds the recall of the
// change evidence; the share in objects with some of it bounds the recall of
// a segmentation that completes each object from its evidence.
#pragma once

#include <lista/missions.hpp>
#include <lista_io/report.hpp>

#include <cstdint>
#include <string>
#include <vector>

struct ObservabilityOptions {
  double rho = 0.05;    // m; a ray or a return this close to a point counts for it
  double margin = 0.1;  // m; a ray must end this far beyond the point to have passed it
  // Points seen empty that make an object's change visible: a segmentation
  // that completes objects can then mark all of it.
  int min_evidence = 10;
  int threads = 2;
};

struct ObjectObservability {
  uint32_t id = 0;
  uint64_t changed = 0, seen_empty = 0, seen_present = 0;
};

struct MissionObservability {
  std::string mission;
  uint64_t changed = 0;       // truly changed points (data contract, sect. 3)
  uint64_t seen_empty = 0;    // a neighbouring mission saw through where they lie
  uint64_t seen_present = 0;  // none saw through, one has a return there
  uint64_t in_visible_objects = 0;  // changed points of objects with min_evidence points seen empty
  std::vector<ObjectObservability> objects;  // by id
};

// One row per mission. Throws lista::Error when a mission has no
// poses_gt.txt with one pose per scan.
std::vector<MissionObservability> observability(const lista::MissionSet& missions,
                                                const lista::io::GroundTruth& truth,
                                                const ObservabilityOptions& options);
