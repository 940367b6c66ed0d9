// Agglomerative (hierarchical) clustering with Lance-Williams updates.
// O(n^2) memory and O(n^3) time: fine for the tens to hundreds of objects a
// change detection produces.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace lista::group {

enum class Linkage { single, average, complete, ward };

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
// The gap cut: undo the merges above the largest relative jump between
// successive merge heights, h_above / h_below, among the cuts into 2 ..
// min(k_max, n / 2) groups (a cut into more groups than half the objects
// would take near-identical pairs, as a moved object described in both
// missions, for classes). A relative jump, not an absolute one: heights
// spread out up the tree, so the largest absolute gap tends to the top.
struct GapCut {
  int k = 1;          // groups kept: best_k, or 1 when its jump is below min_jump
  int best_k = 0;     // the cut with the largest jump (0: none considered, n < 4)
  double jump = 0.0;  // its h_above / h_below - 1 (infinite above a height of 0)
};
GapCut cut_at_largest_gap(int n, const std::vector<Merge>& merges, double min_jump, int k_max);

}  // namespace lista::group
