#pragma once

#include <cstddef>
#include <optional>
#include <vector>

namespace granular {

/// The assignment of least total cost (Kuhn-Munkres, the Hungarian method, O(n^2 m) with
/// potentials) of a rows x columns cost matrix, row-major: each row gets at most one column,
/// each column at most one row, and as many pairs as there are rows or columns, whichever is
/// fewer. Pairs whose cost is not finite are forbidden (a gate): no pair is assigned across
/// them, which may leave rows without a column. Returns, per row, its column or nothing.
/// Throws std::invalid_argument when `costs` does not hold rows * columns values or a cost is
/// NaN.
std::vector<std::optional<std::size_t>> assignMinimumCost(const std::vector<double>& costs,
                                                          std::size_t rows,
                                                          std::size_t columns);

}  // namespace granular
