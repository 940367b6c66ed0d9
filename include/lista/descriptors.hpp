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

struct ObjectSet;

// Empty when `d` keeps the contract above, else what is broken: a row count
// other than the id count, an id given twice, a value that is not finite, or
// (when `normalized`) a row whose L2 norm is not 1 within 1e-3. The core
// checks every `descriptors` output with it, failing the stage that made it.
std::string contract_problem(const DescriptorSet& d);
// The same, and one row per object of `objects` (the stage's input): the
// same ids, none missing, none extra.
std::string contract_problem(const DescriptorSet& d, const ObjectSet& objects);

}  // namespace lista
