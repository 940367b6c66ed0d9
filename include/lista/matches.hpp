// Correspondences between objects of different missions and the resulting
// change status of every object: the content of the change report.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace lista {

enum class ChangeStatus { moved, removed, added };
const char* to_string(ChangeStatus s);  // "moved", "removed", "added"

struct ObjectChange {
  int object_id = -1;
  ChangeStatus status = ChangeStatus::added;
  int match = -1;           // the partner object's id (moved only), else -1
  double cost = 0.0;        // weighted distance to the partner (moved only)
  double confidence = 0.0;  // in [0,1], 1 = most confident
  bool has_transform = false;
  // Maps this object's points onto its partner: p_match = transform * p.
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  // Ids of the same physical object in every mission it was seen in, in
  // mission order (includes object_id). N >= 2 missions.
  std::vector<int> history;
  // Other transforms that fit the partner about as well as `transform` (a
  // symmetric shape turned by 180 degrees, a round one by any angle), best
  // first; empty when the pose is unambiguous or the registration cannot
  // tell. Same convention as `transform`.
  std::vector<Eigen::Matrix4d> alternative_transforms;
};

struct Matches {
  std::string method;
  std::vector<ObjectChange> objects;  // one per object
  const ObjectChange* find(int object_id) const;
  ObjectChange* find(int object_id);
};

}  // namespace lista
