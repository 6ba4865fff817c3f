#include "pf2/humans/assignment.h"

#include <gtest/gtest.h>

namespace pf2 {
namespace {

TEST(Assignment, MinimumTotalCostNotGreedy) {
  // Greedy (cheapest pair first) takes (0,0)=1 and is then forced to (1,1)=10: total 11.
  // The optimum is (0,1)+(1,0) = 2 + 3 = 5.
  const std::vector<int> match = solveAssignment({{1, 2}, {3, 10}}, 100);
  EXPECT_EQ(match, (std::vector<int>{1, 0}));
}

TEST(Assignment, RectangularAndGated) {
  // Three rows, two columns: row 1 is left out.
  EXPECT_EQ(solveAssignment({{1, 5}, {4, 4}, {5, 1}}, 100), (std::vector<int>{0, -1, 1}));
  // Pairs above the limit are never matched, even when that leaves a row alone.
  EXPECT_EQ(solveAssignment({{0.2, 3.0}, {3.0, 3.0}}, 1.0), (std::vector<int>{0, -1}));
  // More matches within the limit beat a lower total: (0,1)+(1,0) = 1.8 over (0,0) alone = 0.1.
  EXPECT_EQ(solveAssignment({{0.1, 0.9}, {0.9, 5.0}}, 1.0), (std::vector<int>{1, 0}));
  EXPECT_TRUE(solveAssignment({}, 1.0).empty());
  EXPECT_EQ(solveAssignment({{}, {}}, 1.0), (std::vector<int>{-1, -1}));
}

}  // namespace
}  // namespace pf2
