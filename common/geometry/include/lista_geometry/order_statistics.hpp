// A median or percentile without a full sort.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace lista::geometry {

// The k-th smallest value of v (0-based); reorders v.
template <class T>
T kth_smallest(std::vector<T>& v, size_t k) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

// The upper median (the middle value, or the higher of the two); reorders v.
template <class T>
T median(std::vector<T>& v) {
  return kth_smallest(v, v.size() / 2);
}

}  // namespace lista::geometry
