// The facts every part of the HTML report draws from, gathered once from the
// stage inputs: per object its mission, status, group, confidence and motion.
#pragma once

#include <lista/data.hpp>

#include <optional>
#include <string>
#include <vector>

namespace lista::report {

// Below this a report is a guess more than a finding: dashed on the maps,
// highlighted in the table.
constexpr double kLowConfidence = 0.5;

struct ObjectView {
  const Object* object = nullptr;
  ChangeStatus status = ChangeStatus::added;
  int group = -1;
  double confidence = 0.0;
  int match = -1;
  std::optional<Eigen::Matrix4d> transform;
  std::vector<Eigen::Matrix4d> alternative_transforms;  // poses that fit about as well (Matches)
  std::vector<int> history;  // the object's reports across the missions (Matches), itself included
};

struct ReportModel {
  std::vector<std::string> missions;
  std::vector<ObjectView> objects;  // in ObjectSet order
  std::vector<Dynamic> dynamics;    // ObjectSet::dynamics: moved during a mission, not changes
  const ObjectView* find(int id) const;
};

// Without `matches`, an object of the first mission is `removed` and any later
// one `added` (the same rule as io.report).
ReportModel build_model(const ObjectSet& objects, const Groups* groups, const Matches* matches);

}  // namespace lista::report
