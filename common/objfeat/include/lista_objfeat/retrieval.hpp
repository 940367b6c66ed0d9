// Instance-retrieval quality of a set of descriptors with known instance
// labels, shared by lista-train (validation) and lista-bench-descriptors.
// Distances are Euclidean between rows.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace lista::objfeat {

using Rows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct RetrievalScores {
  double top1 = 0.0;    // fraction of queries whose nearest other row has the same label
                        // (rows tied at the nearest distance count by the share with it)
  double map = 0.0;     // mean average precision over queries
  double purity = 0.0;  // k-means (k = number of labels) cluster purity
  int queries = 0;      // rows whose label occurs at least twice
  // Per row: 1 when its nearest other row has its label (at least half of
  // the rows tied nearest), 0 when not, -1 when its label is unique (no
  // query: nothing to find, as in top1).
  std::vector<int> top1_hits;
};

// Throws lista::Error if rows and labels differ in count.
RetrievalScores score_retrieval(const Rows& rows, const std::vector<int>& labels, uint64_t seed = 1);

}  // namespace lista::objfeat
