// Agglomerative (hierarchical) clustering with Lance-Williams updates.
// O(n^2) memory and O(n^3) time: fine for the tens to hundreds of objects a
// change detection produces.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace lista::grouping {

enum class Linkage { single, average, complete, ward };
Linkage parse_linkage(const std::string& name);  // throws lista::Error

struct Merge {
  int a, b;       // cluster slots merged (a absorbs b)
  double height;  // linkage distance at the merge (Euclidean units; Ward: sqrt of the variance increase * 2)
};

// The full dendrogram: n-1 merges in order of increasing height.
std::vector<Merge> dendrogram(const Eigen::MatrixXd& x, Linkage linkage);

// Labels (0..k-1, by first appearance) after replaying the first n-k merges.
std::vector<int> cut_to_k(int n, const std::vector<Merge>& merges, int k);
// Number of clusters when every merge above `threshold` is undone.
int k_for_threshold(int n, const std::vector<Merge>& merges, double threshold);
// K at the largest jump between successive merge heights (the dendrogram's
// widest gap): the merges above the gap are undone. 1 for fewer than 3 points
// or when no jump exceeds `min_ratio` times the mean merge height.
int k_at_largest_gap(int n, const std::vector<Merge>& merges, double min_ratio = 0.5);

}  // namespace lista::grouping
