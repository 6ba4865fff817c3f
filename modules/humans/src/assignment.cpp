#include "pf2/humans/assignment.h"

#include <algorithm>
#include <limits>

namespace pf2 {

std::vector<int> solveAssignment(const std::vector<std::vector<double>>& cost, double max_cost) {
  const int rows = static_cast<int>(cost.size());
  const int cols = rows > 0 ? static_cast<int>(cost[0].size()) : 0;
  std::vector<int> match(rows, -1);
  if (rows == 0 || cols == 0) return match;
  // Forbidden pairs and the padding to a square matrix cost more than any allowed assignment in
  // total, so the optimum first matches as many allowed pairs as possible, then minimises cost.
  const int n = std::max(rows, cols);
  const double forbidden = (std::max(max_cost, 0.0) + 1.0) * (n + 1);
  const auto at = [&](int r, int c) {
    if (r >= rows || c >= cols) return forbidden;
    const double value = cost[r][c];
    return value <= max_cost ? value : forbidden;  // NaN lands here too
  };
  // Shortest augmenting paths with row and column potentials (1-based; column 0 is the root).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(n + 1, 0.0);
  std::vector<int> row_of(n + 1, 0), way(n + 1, 0);
  for (int r = 1; r <= n; ++r) {
    row_of[0] = r;
    int c0 = 0;
    std::vector<double> min_to(n + 1, inf);
    std::vector<bool> used(n + 1, false);
    do {
      used[c0] = true;
      const int r0 = row_of[c0];
      double delta = inf;
      int c1 = 0;
      for (int c = 1; c <= n; ++c) {
        if (used[c]) continue;
        const double reduced = at(r0 - 1, c - 1) - u[r0] - v[c];
        if (reduced < min_to[c]) {
          min_to[c] = reduced;
          way[c] = c0;
        }
        if (min_to[c] < delta) {
          delta = min_to[c];
          c1 = c;
        }
      }
      for (int c = 0; c <= n; ++c) {
        if (used[c]) {
          u[row_of[c]] += delta;
          v[c] -= delta;
        } else {
          min_to[c] -= delta;
        }
      }
      c0 = c1;
    } while (row_of[c0] != 0);
    do {
      const int c1 = way[c0];
      row_of[c0] = row_of[c1];
      c0 = c1;
    } while (c0 != 0);
  }
  for (int c = 1; c <= n; ++c) {
    const int r = row_of[c] - 1;
    if (r < rows && c - 1 < cols && at(r, c - 1) < forbidden) match[r] = c - 1;
  }
  return match;
}

}  // namespace pf2
