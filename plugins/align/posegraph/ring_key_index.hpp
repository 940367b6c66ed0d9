// Nearest ring keys by k-d tree (FLANN, exact single-tree index so results do
// not depend on a random seed). FLANN stays inside the .cpp.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace lista::align {

class RingKeyIndex {
 public:
  explicit RingKeyIndex(const std::vector<Eigen::VectorXf>& keys);
  ~RingKeyIndex();
  RingKeyIndex(const RingKeyIndex&) = delete;
  RingKeyIndex& operator=(const RingKeyIndex&) = delete;
  // Indices of up to k nearest keys, nearest first. Thread-safe.
  std::vector<size_t> nearest(const Eigen::VectorXf& key, size_t k) const;
  size_t size() const { return count_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  size_t count_ = 0;
  size_t dim_ = 0;
};

}  // namespace lista::align
