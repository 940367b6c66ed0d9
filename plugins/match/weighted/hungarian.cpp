#include "hungarian.hpp"

#include <lista/error.hpp>

#include <algorithm>
#include <limits>

namespace lista::match {

std::vector<int> hungarian(const Eigen::MatrixXd& cost) {
  const int n = static_cast<int>(cost.rows()), m = static_cast<int>(cost.cols());
  if (n == 0) return {};
  if (n > m) throw Error("hungarian: more rows than columns");
  if (!cost.allFinite()) throw Error("hungarian: non-finite cost");
  const double inf = std::numeric_limits<double>::infinity();
  // 1-based arrays; column 0 is the virtual start. u/v are the dual
  // potentials, p[j] the row matched to column j, way[] the augmenting path.
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<bool> used(m + 1, false);
    do {
      used[j0] = true;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = cost(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) u[p[j]] += delta, v[j] -= delta;
        else minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {  // flip the augmenting path
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> row_to_col(n, -1);
  for (int j = 1; j <= m; ++j)
    if (p[j] != 0) row_to_col[p[j] - 1] = j - 1;
  return row_to_col;
}

std::vector<int> assign_with_gate(const Eigen::MatrixXd& cost,
                                  const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& allowed,
                                  double leave) {
  const int n = static_cast<int>(cost.rows()), m = static_cast<int>(cost.cols());
  std::vector<int> result(n, -1);
  if (n == 0 || m == 0) return result;
  // Square (n+m) matrix: [real pairs | row i alone] over [column j alone | dummy-dummy].
  // Forbidden entries cost more than any feasible full assignment, so they
  // are never chosen while leaving everything alone is always feasible.
  double worst = std::max(leave, 0.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (allowed(i, j)) worst = std::max(worst, cost(i, j));
  const double big = (worst + 1.0) * (n + m + 1) * 4.0;
  const int s = n + m;
  Eigen::MatrixXd c = Eigen::MatrixXd::Constant(s, s, big);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
      if (allowed(i, j)) c(i, j) = cost(i, j);
  for (int i = 0; i < n; ++i) c(i, m + i) = leave / 2;
  for (int j = 0; j < m; ++j) c(n + j, j) = leave / 2;
  c.bottomRightCorner(m, n).setZero();
  const std::vector<int> a = hungarian(c);
  for (int i = 0; i < n; ++i)
    if (a[i] < m && allowed(i, a[i]) && cost(i, a[i]) < leave) result[i] = a[i];
  return result;
}

}  // namespace lista::match
