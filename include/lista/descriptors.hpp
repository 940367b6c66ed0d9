// Object-level descriptors: one row per object. Every describe.* plugin
// outputs this one type, so grouping and matching never care which is used.
// Per-point descriptors (SHOT, RIFT) are reduced to one vector per object by
// the plugin (its doc says how).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace lista {

struct DescriptorSet {
  using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  std::string method;           // plugin name, e.g. "describe.learned"
  std::vector<int> object_ids;  // row i describes object object_ids[i]
  Matrix values;                // rows = objects, cols = dimension
  bool normalized = false;      // rows have unit L2 norm
  int dim() const { return static_cast<int>(values.cols()); }
  int row_of(int object_id) const;  // -1 if absent
};

}  // namespace lista
