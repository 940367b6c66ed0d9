#include <lista_grouping/group_result.hpp>

#include <lista/error.hpp>

#include <algorithm>
#include <cmath>

namespace lista::grouping {

Eigen::MatrixXd to_double(const DescriptorSet& d) { return d.values.cast<double>(); }

void check_descriptors(const DescriptorSet& d) {
  if (static_cast<size_t>(d.values.rows()) != d.object_ids.size())
    throw Error("descriptors have " + std::to_string(d.values.rows()) + " rows but " +
                std::to_string(d.object_ids.size()) + " object ids");
  if (!d.values.allFinite()) throw Error("descriptors contain NaN or infinite values");
}

Groups make_groups(const std::string& method, const std::vector<int>& object_ids,
                   const Eigen::MatrixXd& x, const std::vector<int>& labels) {
  Groups g;
  g.method = method;
  g.object_ids = object_ids;
  g.group = labels;
  const int n = static_cast<int>(labels.size());
  int k = 0;
  for (int l : labels) k = std::max(k, l + 1);
  g.count = k;
  if (n == 0) return g;

  Eigen::MatrixXd centroid = Eigen::MatrixXd::Zero(k, x.cols());
  std::vector<int> size(k, 0);
  for (int i = 0; i < n; ++i) {
    centroid.row(labels[i]) += x.row(i);
    ++size[labels[i]];
  }
  for (int c = 0; c < k; ++c) {
    if (size[c] == 0) throw Error("internal: empty cluster " + std::to_string(c));
    centroid.row(c) /= size[c];
  }

  std::vector<double> dist(n), mean(k, 0.0);
  double dmax = 0.0;
  for (int i = 0; i < n; ++i) {
    dist[i] = (x.row(i) - centroid.row(labels[i])).norm();
    mean[labels[i]] += dist[i] / size[labels[i]];
    dmax = std::max(dmax, dist[i]);
  }
  const auto [lo, hi] = std::minmax_element(mean.begin(), mean.end());
  const double range = *hi - *lo;
  g.group_confidence.resize(k);
  for (int c = 0; c < k; ++c)
    g.group_confidence[c] = range > 1e-12 ? 1.0 - (mean[c] - *lo) / range : 1.0;
  g.confidence.resize(n);
  for (int i = 0; i < n; ++i) g.confidence[i] = dmax > 1e-12 ? 1.0 - dist[i] / dmax : 1.0;
  return g;
}

}  // namespace lista::grouping
