// report.json and ground_truth.json (data contract, sect. 2 and 3), as plain
// structs with JSON reading (strict: a missing or mistyped field is a
// lista::Error naming the file and the field) and atomic writing.
#pragma once

#include <Eigen/Core>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace lista::io {

struct ReportObject {
  int id = -1;
  std::string mission;
  std::string status;  // "moved", "removed", "added"
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero(), bbox_max = Eigen::Vector3d::Zero();
  size_t points = 0;
  int group = -1;
  double confidence = 0.0;
  int match = -1;                            // -1 is written as null
  std::optional<Eigen::Matrix4d> transform;  // moved only
  // Extension, moved only: other transforms that fit about as well (a
  // symmetric shape's half-turn), best first; empty: unambiguous.
  std::vector<Eigen::Matrix4d> alternative_transforms;
  std::vector<int> history;                  // extension: ids across missions
  std::optional<double> floor_z;             // extension: floor under the object (common frame), null if unknown
};

struct Report {
  std::string format = "lista-report/1";
  std::vector<std::string> missions;
  std::map<std::string, Eigen::Matrix4d> alignment;
  std::vector<ReportObject> objects;
  std::vector<std::pair<std::string, double>> timings_s;  // stage order
  std::string extra_json = "{}";  // provenance, metrics...: a JSON object merged at top level
};

void write_report(const std::string& path, const Report& report);  // atomic
Report read_report(const std::string& path);

struct TruthObject {
  int id = 0;
  std::string class_name;
  bool dynamic = false;
  std::map<std::string, std::optional<Eigen::Matrix4d>> poses;  // per mission; nullopt = absent
};

struct GroundTruth {
  std::string format = "lista-ground-truth/1";
  std::vector<std::string> missions;
  std::map<std::string, Eigen::Matrix4d> mission_to_world;
  std::vector<TruthObject> objects;
};

void write_ground_truth(const std::string& path, const GroundTruth& truth);  // atomic
GroundTruth read_ground_truth(const std::string& path);

}  // namespace lista::io
