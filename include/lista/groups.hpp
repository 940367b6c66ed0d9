// Groups (classes) of objects found by clustering their descriptors.
#pragma once

#include <string>
#include <vector>

namespace lista {

struct Groups {
  std::string method;            // plugin name, e.g. "group.kmeans"
  std::vector<int> object_ids;   // one entry per object
  std::vector<int> group;        // group id of object_ids[i], 0..count-1
  std::vector<double> confidence;        // per object, in [0,1], 1 = most confident
  std::vector<double> group_confidence;  // per group, in [0,1], 1 = most compact
  int count = 0;
  int group_of(int object_id) const;  // -1 if absent
};

}  // namespace lista
