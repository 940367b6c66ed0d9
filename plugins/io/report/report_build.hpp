// Turning the pipeline's typed results into the contract's report.json
// content and change clouds (data contract, sect. 2).
#pragma once

#include <lista/lista.hpp>
#include <lista_io/poses.hpp>
#include <lista_io/report.hpp>

#include <string>
#include <vector>

namespace lista::io {

// The rows of changes/<mission>.pcd for one mission.
struct ChangeCloud {
  std::string mission;
  std::vector<float> x, y, z;
  std::vector<uint32_t> scan, index;
  std::vector<int32_t> object;
  size_t size() const { return x.size(); }
  void push_back(const Eigen::Vector3f& p, uint32_t scan, uint32_t index, int32_t object);
  void append(const ChangeCloud& other);  // other's rows after these
};

// poses/<mission>.txt: every scan's sensor pose in the common frame, as the
// run placed it (the aligner may correct each scan, which `alignment` alone
// does not say), TUM layout with the scan's timestamp.
struct ScanPoses {
  std::string mission;
  std::vector<io::PoseRecord> poses;
};

struct Built {
  io::Report report;
  std::vector<ChangeCloud> clouds;  // one per mission, MissionSet order
  std::vector<ScanPoses> poses;     // one per mission, MissionSet order
  std::vector<std::string> warnings;
};

// groups, matches and changes may be null (unconnected). Without matches the
// status is by mission order: objects of the first mission "removed", of later
// ones "added". A moved object without a transform gets the translation
// between the two objects' centroids (and a warning).
Built build_report(const MissionSet& missions, const ObjectSet& objects, const Groups* groups,
                   const Matches* matches, const MissionPoints* changes);

// Provenance, metrics and warnings of the run, `local_origin` (where the
// run's local frame lies in the dataset's coordinates: MissionSet::origin)
// and the objects' dynamics (what moved during a mission, in the dataset's
// coordinates), as the report's extra top-level JSON.
std::string provenance_json(const RunInfo& run, const Eigen::Vector3d& local_origin, const ObjectSet& objects);

}  // namespace lista::io
