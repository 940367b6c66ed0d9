#include "kmeans.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

namespace lista::group {

namespace {

// k-means++ (Arthur & Vassilvitskii 2007): each next centre is drawn with
// probability proportional to the squared distance to the nearest centre.
Eigen::MatrixXd seed_plus_plus(const Eigen::MatrixXd& x, int k, std::mt19937_64& rng) {
  const int n = static_cast<int>(x.rows());
  Eigen::MatrixXd c(k, x.cols());
  std::uniform_int_distribution<int> pick(0, n - 1);
  c.row(0) = x.row(pick(rng));
  std::vector<double> d2(n, std::numeric_limits<double>::max());
  for (int j = 1; j < k; ++j) {
    double total = 0.0;
    for (int i = 0; i < n; ++i) {
      d2[i] = std::min(d2[i], (x.row(i) - c.row(j - 1)).squaredNorm());
      total += d2[i];
    }
    int chosen = 0;
    if (total <= 0.0) {
      chosen = pick(rng);  // all points coincide with centres: any will do
    } else {
      std::uniform_real_distribution<double> u(0.0, total);
      double r = u(rng), acc = 0.0;
      chosen = n - 1;
      for (int i = 0; i < n; ++i) {
        acc += d2[i];
        if (acc >= r && d2[i] > 0.0) {
          chosen = i;
          break;
        }
      }
    }
    c.row(j) = x.row(chosen);
  }
  return c;
}

KMeansResult lloyd(const Eigen::MatrixXd& x, Eigen::MatrixXd c, int max_iterations) {
  const int n = static_cast<int>(x.rows()), k = static_cast<int>(c.rows());
  KMeansResult r;
  r.labels.assign(n, -1);
  for (int it = 0; it < max_iterations; ++it) {
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      int best = 0;
      double bd = std::numeric_limits<double>::max();
      for (int j = 0; j < k; ++j) {
        const double d = (x.row(i) - c.row(j)).squaredNorm();
        if (d < bd) bd = d, best = j;
      }
      if (r.labels[i] != best) r.labels[i] = best, changed = true;
    }
    // An empty cluster takes the point farthest from its centre, so k stays k.
    std::vector<int> size(k, 0);
    for (int l : r.labels) ++size[l];
    for (int j = 0; j < k; ++j) {
      if (size[j] > 0) continue;
      int far = 0;
      double fd = -1.0;
      for (int i = 0; i < n; ++i) {
        if (size[r.labels[i]] <= 1) continue;
        const double d = (x.row(i) - c.row(r.labels[i])).squaredNorm();
        if (d > fd) fd = d, far = i;
      }
      --size[r.labels[far]];
      r.labels[far] = j;
      ++size[j];
      changed = true;
    }
    c.setZero();
    for (int i = 0; i < n; ++i) c.row(r.labels[i]) += x.row(i);
    for (int j = 0; j < k; ++j) c.row(j) /= size[j];
    if (!changed) break;
  }
  r.wcss = 0.0;
  for (int i = 0; i < n; ++i) r.wcss += (x.row(i) - c.row(r.labels[i])).squaredNorm();
  return r;
}

// Labels renumbered by first appearance, so equal partitions give equal output.
void canonical_labels(std::vector<int>& labels) {
  std::vector<int> map;
  int next = 0;
  for (int& l : labels) {
    if (l >= static_cast<int>(map.size())) map.resize(l + 1, -1);
    if (map[l] < 0) map[l] = next++;
    l = map[l];
  }
}

}  // namespace

KMeansResult kmeans(const Eigen::MatrixXd& x, int k, const KMeansConfig& cfg) {
  const int n = static_cast<int>(x.rows());
  if (k < 1 || k > n)
    throw Error("k-means: k = " + std::to_string(k) + " must be in [1, " + std::to_string(n) + "]");
  KMeansResult best;
  best.wcss = std::numeric_limits<double>::max();
  for (int r = 0; r < std::max(1, cfg.restarts); ++r) {
    // One stream per (seed, k, restart): results do not depend on the order
    // in which K values are tried.
    std::seed_seq seq{static_cast<uint32_t>(cfg.seed), static_cast<uint32_t>(cfg.seed >> 32),
                      static_cast<uint32_t>(k), static_cast<uint32_t>(r)};
    std::mt19937_64 rng(seq);
    KMeansResult res = lloyd(x, seed_plus_plus(x, k, rng), cfg.max_iterations);
    if (res.wcss < best.wcss - 1e-12) best = std::move(res);
  }
  canonical_labels(best.labels);
  return best;
}

int elbow_k(const std::vector<double>& wcss, double flat_tolerance) {
  const int m = static_cast<int>(wcss.size());
  if (m < 3) return 1;
  const double top = wcss.front(), bottom = wcss.back();
  if (top - bottom <= flat_tolerance * std::max(top, 1e-300) || top <= 0.0) return 1;
  int best = 1;
  double best_gap = 0.0;
  for (int i = 1; i < m - 1; ++i) {
    const double xk = static_cast<double>(i) / (m - 1);
    const double yk = (wcss[i] - bottom) / (top - bottom);
    // Chord y = 1 - x; distance below it is (1 - x - y) / sqrt(2).
    const double gap = 1.0 - xk - yk;
    if (gap > best_gap + 1e-12) best_gap = gap, best = i + 1;
  }
  return best;
}

}  // namespace lista::group
