// Disjoint sets over 0..n-1, header only. The smaller root wins a union, so
// which element roots a set does not depend on the order of the unions.
#pragma once

#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace lista::geometry {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), size_t(0)); }

  size_t find(size_t a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];  // path halving
    return a;
  }

  void unite(size_t a, size_t b) {
    a = find(a), b = find(b);
    if (a == b) return;
    if (a < b) std::swap(a, b);
    parent_[a] = b;
  }

 private:
  std::vector<size_t> parent_;
};

}  // namespace lista::geometry
