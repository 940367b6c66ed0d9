#include "agglomerative.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace lista::grouping {

Linkage parse_linkage(const std::string& name) {
  if (name == "single") return Linkage::single;
  if (name == "average") return Linkage::average;
  if (name == "complete") return Linkage::complete;
  if (name == "ward") return Linkage::ward;
  throw Error("unknown linkage '" + name + "' (single, average, complete, ward)");
}

std::vector<Merge> dendrogram(const Eigen::MatrixXd& x, Linkage linkage) {
  const int n = static_cast<int>(x.rows());
  // Ward works on squared distances (Lance-Williams form); the others on distances.
  const bool squared = linkage == Linkage::ward;
  Eigen::MatrixXd d(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double s = (x.row(i) - x.row(j)).squaredNorm();
      d(i, j) = squared ? s : std::sqrt(s);
    }
  std::vector<int> size(n, 1);
  std::vector<bool> alive(n, true);
  std::vector<Merge> merges;
  for (int step = 0; step + 1 < n; ++step) {
    int a = -1, b = -1;
    double best = std::numeric_limits<double>::max();
    for (int i = 0; i < n; ++i) {
      if (!alive[i]) continue;
      for (int j = i + 1; j < n; ++j)
        if (alive[j] && d(i, j) < best) best = d(i, j), a = i, b = j;
    }
    for (int k = 0; k < n; ++k) {
      if (!alive[k] || k == a || k == b) continue;
      const double da = d(a, k), db = d(b, k), na = size[a], nb = size[b], nk = size[k];
      double v = 0.0;
      switch (linkage) {
        case Linkage::single: v = std::min(da, db); break;
        case Linkage::complete: v = std::max(da, db); break;
        case Linkage::average: v = (na * da + nb * db) / (na + nb); break;
        case Linkage::ward:
          v = ((na + nk) * da + (nb + nk) * db - nk * best) / (na + nb + nk);
          break;
      }
      d(a, k) = d(k, a) = v;
    }
    size[a] += size[b];
    alive[b] = false;
    merges.push_back({a, b, squared ? std::sqrt(std::max(0.0, best)) : best});
  }
  return merges;
}

std::vector<int> cut_to_k(int n, const std::vector<Merge>& merges, int k) {
  k = std::clamp(k, std::min(n, 1), n);
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int m = 0; m < n - k; ++m) parent[root(merges[m].b)] = root(merges[m].a);
  std::vector<int> labels(n), map(n, -1);
  int next = 0;
  for (int i = 0; i < n; ++i) {
    const int r = root(i);
    if (map[r] < 0) map[r] = next++;
    labels[i] = map[r];
  }
  return labels;
}

int k_for_threshold(int n, const std::vector<Merge>& merges, double threshold) {
  int done = 0;
  for (const Merge& m : merges)
    if (m.height <= threshold) ++done;
  return std::max(n - done, std::min(n, 1));
}

int k_at_largest_gap(int n, const std::vector<Merge>& merges, double min_ratio) {
  if (n < 3) return std::min(n, 1);
  // Heights are non-decreasing for these linkages; sort anyway for safety.
  std::vector<double> h;
  for (const Merge& m : merges) h.push_back(m.height);
  std::sort(h.begin(), h.end());
  const double mean = std::accumulate(h.begin(), h.end(), 0.0) / h.size();
  double best_gap = 0.0;
  int best_done = static_cast<int>(h.size());  // merges kept below the gap
  // Gap before the first merge counts from 0: all points distinct clusters is
  // never chosen unless the data are one point per class by a wide margin.
  for (size_t i = 1; i < h.size(); ++i) {
    const double gap = h[i] - h[i - 1];
    if (gap > best_gap) best_gap = gap, best_done = static_cast<int>(i);
  }
  if (best_gap <= min_ratio * mean) return 1;
  return n - best_done;
}

}  // namespace lista::grouping
