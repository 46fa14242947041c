#include "granular_core/tracking/assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace granular {

std::vector<std::optional<std::size_t>> assignMinimumCost(const std::vector<double>& costs,
                                                          std::size_t rows,
                                                          std::size_t columns) {
  if (costs.size() != rows * columns) {
    throw std::invalid_argument("assignMinimumCost: " + std::to_string(costs.size()) +
                                " costs for a " + std::to_string(rows) + " x " +
                                std::to_string(columns) + " matrix");
  }
  std::vector<std::optional<std::size_t>> assigned(rows);
  if (rows == 0 || columns == 0) {
    return assigned;
  }
  // A forbidden pair costs more than any two assignments of allowed pairs can differ by, so
  // the method (which needs finite costs) assigns as many allowed pairs as it can, at the
  // least cost among those; the forbidden pairs it had to take are dropped afterwards.
  double largest = 0.0;
  for (const double cost : costs) {
    if (std::isnan(cost)) {
      throw std::invalid_argument("assignMinimumCost: a cost is NaN");
    }
    if (std::isfinite(cost)) {
      largest = std::max(largest, std::abs(cost));
    }
  }
  const double forbidden =
      2.0 * (largest + 1.0) * static_cast<double>(std::min(rows, columns) + 1);
  // The method below needs rows <= columns: a tall matrix is solved transposed.
  const bool transposed = rows > columns;
  const std::size_t n = transposed ? columns : rows;
  const std::size_t m = transposed ? rows : columns;
  const auto cost = [&](std::size_t i, std::size_t j) {  // 1-based, as the method counts
    const double value = transposed ? costs[(j - 1) * columns + (i - 1)]
                                    : costs[(i - 1) * columns + (j - 1)];
    return std::isfinite(value) ? value : forbidden;
  };

  // Row potentials u, column potentials v; owner[j]: the row holding column j (0: none);
  // column 0 is the sentinel the augmenting path starts from.
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0);
  std::vector<std::size_t> owner(m + 1, 0), way(m + 1, 0);
  for (std::size_t i = 1; i <= n; ++i) {
    owner[0] = i;
    std::size_t j0 = 0;
    std::vector<double> slack(m + 1, infinity);
    std::vector<bool> used(m + 1, false);
    do {
      used[j0] = true;
      const std::size_t i0 = owner[j0];
      double delta = infinity;
      std::size_t j1 = 0;
      for (std::size_t j = 1; j <= m; ++j) {
        if (used[j]) {
          continue;
        }
        const double reduced = cost(i0, j) - u[i0] - v[j];
        if (reduced < slack[j]) {
          slack[j] = reduced;
          way[j] = j0;
        }
        if (slack[j] < delta) {
          delta = slack[j];
          j1 = j;
        }
      }
      for (std::size_t j = 0; j <= m; ++j) {
        if (used[j]) {
          u[owner[j]] += delta;
          v[j] -= delta;
        } else {
          slack[j] -= delta;
        }
      }
      j0 = j1;
    } while (owner[j0] != 0);
    do {  // augment along the path
      const std::size_t j1 = way[j0];
      owner[j0] = owner[j1];
      j0 = j1;
    } while (j0 != 0);
  }

  for (std::size_t j = 1; j <= m; ++j) {
    if (owner[j] == 0) {
      continue;
    }
    const std::size_t row = transposed ? j - 1 : owner[j] - 1;
    const std::size_t column = transposed ? owner[j] - 1 : j - 1;
    if (std::isfinite(costs[row * columns + column])) {
      assigned[row] = column;
    }
  }
  return assigned;
}

}  // namespace granular
