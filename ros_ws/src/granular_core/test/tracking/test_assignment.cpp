// The least-cost assignment: the optimum where greedy choice misses it, the same total as every
// permutation tried, rectangular matrices both ways, and gates that are never crossed.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/tracking/assignment.h"

namespace granular {
namespace {

constexpr double kGated = std::numeric_limits<double>::infinity();

double totalCost(const std::vector<double>& costs, std::size_t columns,
                 const std::vector<std::optional<std::size_t>>& assigned) {
  double total = 0.0;
  for (std::size_t row = 0; row < assigned.size(); ++row) {
    if (assigned[row]) {
      total += costs[row * columns + *assigned[row]];
    }
  }
  return total;
}

// The least total over every way of giving each row of a rows <= columns matrix a column.
double bruteForceMinimum(const std::vector<double>& costs, std::size_t rows,
                         std::size_t columns) {
  std::vector<std::size_t> order(columns);
  std::iota(order.begin(), order.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do {
    double total = 0.0;
    for (std::size_t row = 0; row < rows; ++row) {
      total += costs[row * columns + order[row]];
    }
    best = std::min(best, total);
  } while (std::next_permutation(order.begin(), order.end()));
  return best;
}

TEST(AssignmentTest, FindsTheOptimumWhereTheGreedyChoiceMissesIt) {
  // Greedy takes (0, 0) at 1 and is left with (1, 1) at 10: 11. The optimum is 2 + 3 = 5.
  const std::vector<double> costs = {1, 2,
                                     3, 10};
  const auto assigned = assignMinimumCost(costs, 2, 2);
  ASSERT_TRUE(assigned[0] && assigned[1]);
  EXPECT_EQ(*assigned[0], 1u);
  EXPECT_EQ(*assigned[1], 0u);
}

TEST(AssignmentTest, MatchesEveryPermutationOnRandomMatricesOfEitherShape) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> cost(0.0, 10.0);
  for (int trial = 0; trial < 200; ++trial) {
    const std::size_t rows = 1 + trial % 6;
    const std::size_t columns = 1 + (trial / 6) % 6;
    std::vector<double> costs(rows * columns);
    for (double& c : costs) {
      c = cost(random);
    }
    const auto assigned = assignMinimumCost(costs, rows, columns);
    ASSERT_EQ(assigned.size(), rows);
    std::vector<bool> used(columns, false);
    std::size_t pairs = 0;
    for (const auto& column : assigned) {
      if (column) {
        ASSERT_LT(*column, columns);
        ASSERT_FALSE(used[*column]) << "column " << *column << " given twice";
        used[*column] = true;
        ++pairs;
      }
    }
    EXPECT_EQ(pairs, std::min(rows, columns));
    // The brute force wants rows <= columns: a tall matrix is checked transposed.
    double best;
    if (rows <= columns) {
      best = bruteForceMinimum(costs, rows, columns);
    } else {
      std::vector<double> transposed(costs.size());
      for (std::size_t r = 0; r < rows; ++r) {
        for (std::size_t c = 0; c < columns; ++c) {
          transposed[c * rows + r] = costs[r * columns + c];
        }
      }
      best = bruteForceMinimum(transposed, columns, rows);
    }
    EXPECT_NEAR(totalCost(costs, columns, assigned), best, 1e-9)
        << rows << " x " << columns << ", trial " << trial;
  }
}

TEST(AssignmentTest, NeverPairsAcrossAGateAndPairsAsManyAsTheGatesAllow) {
  // Row 1 may only take column 0, so row 0 takes its dearer column 1: two pairs (102) rather
  // than the one cheapest pair (row 0, column 0 at 1).
  const std::vector<double> costs = {1, 100,
                                     2, kGated};
  const auto assigned = assignMinimumCost(costs, 2, 2);
  ASSERT_TRUE(assigned[0] && assigned[1]);
  EXPECT_EQ(*assigned[0], 1u);
  EXPECT_EQ(*assigned[1], 0u);

  // Both rows may only take column 0: the cheaper gets it, the other nothing.
  const auto shared = assignMinimumCost({3, kGated, 1, kGated}, 2, 2);
  EXPECT_FALSE(shared[0]);
  ASSERT_TRUE(shared[1]);
  EXPECT_EQ(*shared[1], 0u);

  const auto none = assignMinimumCost({kGated, kGated, kGated}, 1, 3);
  EXPECT_FALSE(none[0]);
}

TEST(AssignmentTest, EmptyMatricesAndBadInput) {
  EXPECT_EQ(assignMinimumCost({}, 0, 3).size(), 0u);
  const auto no_columns = assignMinimumCost({}, 2, 0);
  ASSERT_EQ(no_columns.size(), 2u);
  EXPECT_FALSE(no_columns[0] || no_columns[1]);
  EXPECT_THROW(assignMinimumCost({1, 2, 3}, 2, 2), std::invalid_argument);
  EXPECT_THROW(assignMinimumCost({1, std::nan("")}, 1, 2), std::invalid_argument);
}

}  // namespace
}  // namespace granular
