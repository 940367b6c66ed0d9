// K-means (Lloyd) with k-means++ seeding and the elbow rule for K.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace lista::group {

struct KMeansConfig {
  int restarts = 10;         // independent seedings; the lowest WCSS wins
  int max_iterations = 300;  // Lloyd iterations per restart
  uint64_t seed = 0;
};

struct KMeansResult {
  std::vector<int> labels;  // 0..k-1, every label used
  double wcss = 0.0;        // within-cluster sum of squared distances
};

// Clusters the rows of x into k groups (1 <= k <= rows). Deterministic for a seed.
KMeansResult kmeans(const Eigen::MatrixXd& x, int k, const KMeansConfig& cfg);

// The elbow of a WCSS curve given for K = 1..wcss.size():
// both axes are normalised to [0,1] (K by (K-1)/(Kmax-1), WCSS by
// (W(K)-W(Kmax))/(W(1)-W(Kmax))) and the K whose point lies farthest below
// the chord from (K=1, W(1)) to (K=Kmax, W(Kmax)) is chosen. Returns 1 when
// fewer than 3 values are given (no interior point, no elbow) or when the
// curve is flat (W(1) - W(Kmax) <= flat_tolerance * W(1), i.e. splitting
// does not explain the data better: one class).
int elbow_k(const std::vector<double>& wcss, double flat_tolerance = 1e-9);

}  // namespace lista::group
