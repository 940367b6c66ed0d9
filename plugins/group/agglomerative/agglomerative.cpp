#include "agglomerative.hpp"

#include <lista/error.hpp>
#include <lista_geometry/union_find.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace lista::group {

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
  geometry::UnionFind sets{size_t(n)};
  for (int m = 0; m < n - k; ++m) sets.unite(size_t(merges[m].a), size_t(merges[m].b));
  std::vector<int> labels(n), map(n, -1);
  int next = 0;
  for (int i = 0; i < n; ++i) {
    const size_t r = sets.find(size_t(i));
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

GapCut cut_at_largest_gap(int n, const std::vector<Merge>& merges, double min_jump, int k_max) {
  GapCut cut;
  // Heights are non-decreasing for these linkages; sort anyway for safety.
  std::vector<double> h;
  for (const Merge& m : merges) h.push_back(m.height);
  std::sort(h.begin(), h.end());
  const int last = std::min(k_max, n / 2);
  // Cutting into k groups undoes the top k-1 merges: the lowest undone one is
  // h[n-k], the highest kept one h[n-k-1]. Ties go to the fewer groups.
  for (int k = 2; k <= last && n - k - 1 >= 0; ++k) {
    const double above = h[n - k], below = h[n - k - 1];
    const double jump = below > 0.0 ? above / below - 1.0 : (above > 0.0 ? std::numeric_limits<double>::infinity() : 0.0);
    if (cut.best_k == 0 || jump > cut.jump) cut.best_k = k, cut.jump = jump;
  }
  cut.k = cut.best_k > 0 && cut.jump >= min_jump ? cut.best_k : 1;
  return cut;
}

}  // namespace lista::group
