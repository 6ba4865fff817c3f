#pragma once
// Minimum-cost one-to-one assignment (Hungarian method, O(n^3)) for matching people between
// frames and against ground truth.
#include <vector>

namespace pf2 {

// cost[r][c] for r < rows, c < cols (a rectangular matrix; all rows the same length). Pairs with a
// cost above max_cost are never matched. Returns, per row, the matched column or -1; the sum of
// the matched costs is minimal among assignments that match as many pairs as possible within
// max_cost. Thread safe.
std::vector<int> solveAssignment(const std::vector<std::vector<double>>& cost, double max_cost);

}  // namespace pf2
