// Optimal assignment (Hungarian algorithm, Kuhn-Munkres with potentials,
// O(n^2 m)). Used instead of a greedy nearest match so that one object's
// best partner cannot be stolen at the expense of a worse total.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace lista::match {

// Minimum-cost assignment of every row of `cost` (rows <= cols) to a distinct
// column. Returns the column of each row. Costs must be finite.
std::vector<int> hungarian(const Eigen::MatrixXd& cost);

// Assignment where a row or column may stay unassigned: pairing row i with
// column j costs cost(i,j) (only where allowed(i,j)), leaving any row or column
// alone costs `leave` / 2, so a pair is used only if it costs less than
// `leave`. Returns the column of each row or -1. Any shape.
std::vector<int> assign_with_gate(const Eigen::MatrixXd& cost,
                                  const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& allowed,
                                  double leave);

}  // namespace lista::match
