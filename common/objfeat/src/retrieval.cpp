#include <lista_objfeat/retrieval.hpp>

#include <lista/error.hpp>

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <random>

namespace lista::objfeat {
namespace {

// Lloyd's k-means with k-means++ seeding; returns the assignment.
std::vector<int> kmeans(const Rows& x, int k, uint64_t seed) {
  const int n = int(x.rows());
  std::mt19937_64 rng(seed);
  Rows c(k, x.cols());
  c.row(0) = x.row(std::uniform_int_distribution<int>(0, n - 1)(rng));
  std::vector<double> d2(n, std::numeric_limits<double>::max());
  for (int j = 1; j < k; ++j) {
    for (int i = 0; i < n; ++i) d2[i] = std::min(d2[i], double((x.row(i) - c.row(j - 1)).squaredNorm()));
    std::discrete_distribution<int> pick(d2.begin(), d2.end());
    c.row(j) = x.row(pick(rng));
  }
  std::vector<int> a(n, -1);
  for (int iter = 0; iter < 50; ++iter) {
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      Eigen::Index best;
      (c.rowwise() - x.row(i)).rowwise().squaredNorm().minCoeff(&best);
      if (a[i] != int(best)) { a[i] = int(best); changed = true; }
    }
    if (!changed) break;
    Rows sum = Rows::Zero(k, x.cols());
    std::vector<int> cnt(k, 0);
    for (int i = 0; i < n; ++i) { sum.row(a[i]) += x.row(i); ++cnt[a[i]]; }
    for (int j = 0; j < k; ++j)
      if (cnt[j] > 0) c.row(j) = sum.row(j) / float(cnt[j]);
  }
  return a;
}

}  // namespace

RetrievalScores score_retrieval(const Rows& x, const std::vector<int>& labels, uint64_t seed) {
  if (size_t(x.rows()) != labels.size()) throw Error("descriptor rows and labels differ in count");
  RetrievalScores s;
  const int n = int(x.rows());
  if (n < 2) return s;
  std::map<int, int> count;
  for (int l : labels) ++count[l];

  double top1 = 0.0, map = 0.0;
  s.top1_hits.assign(size_t(n), -1);
  std::vector<std::pair<float, int>> ranked;
  for (int q = 0; q < n; ++q) {
    if (count[labels[q]] < 2) continue;
    ranked.clear();
    for (int j = 0; j < n; ++j)
      if (j != q) ranked.emplace_back((x.row(j) - x.row(q)).squaredNorm(), j);
    std::sort(ranked.begin(), ranked.end());
    // Rows tied at the nearest distance are equally near: the query gets the
    // share of them with its label, not whichever comes first in row order
    // (a constant descriptor scores chance, not chance plus tie order).
    size_t tied = 0, same = 0;
    for (; tied < ranked.size() && ranked[tied].first == ranked[0].first; ++tied)
      same += labels[ranked[tied].second] == labels[q];
    const double share = double(same) / double(tied);
    s.top1_hits[size_t(q)] = share >= 0.5;
    top1 += share;
    int hits = 0;
    double ap = 0.0;
    for (size_t r = 0; r < ranked.size(); ++r)
      if (labels[ranked[r].second] == labels[q]) ap += double(++hits) / double(r + 1);
    map += ap / double(hits);
    ++s.queries;
  }
  if (s.queries > 0) {
    s.top1 = top1 / s.queries;
    s.map = map / s.queries;
  }

  int k = std::min<int>(int(count.size()), n);
  std::vector<int> a = kmeans(x, k, seed);
  std::vector<std::map<int, int>> members(k);
  for (int i = 0; i < n; ++i) ++members[a[i]][labels[i]];
  int pure = 0;
  for (const auto& m : members) {
    int best = 0;
    for (const auto& [l, c] : m) best = std::max(best, c);
    pure += best;
  }
  s.purity = double(pure) / n;
  return s;
}

}  // namespace lista::objfeat
