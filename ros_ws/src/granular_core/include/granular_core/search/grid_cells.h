#pragma once

// Uniform 3-D grids of cells stored x fastest, as NearestGrid, NdtMatcher and the point
// histograms' CellIndex keep them (a header of the library's sources, not of its interface).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granular {

/// The box of `count` points (at least one) given as x y z floats: its corners, x y z.
inline void boxOfPoints(const float* xyz, std::size_t count, float low[3], float high[3]) {
  for (int axis = 0; axis < 3; ++axis) {
    low[axis] = high[axis] = xyz[axis];
  }
  for (std::size_t i = 1; i < count; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = std::min(low[axis], xyz[3 * i + axis]);
      high[axis] = std::max(high[axis], xyz[3 * i + axis]);
    }
  }
}

/// Calls visit(cell) for every cell of the box of cells [low, high] (x y z) that lies in a
/// grid of `size` cells, cell = (z * size[1] + y) * size[0] + x.
template <typename Visit>
void forEachCell(const int low[3], const int high[3], const int size[3], Visit visit) {
  for (int z = std::max(low[2], 0); z <= std::min(high[2], size[2] - 1); ++z) {
    for (int y = std::max(low[1], 0); y <= std::min(high[1], size[1] - 1); ++y) {
      for (int x = std::max(low[0], 0); x <= std::min(high[0], size[0] - 1); ++x) {
        visit((static_cast<std::size_t>(z) * size[1] + y) * size[0] + x);
      }
    }
  }
}

/// The cell of a grid of `size` cells `cell` wide from `origin` that holds `point`: its
/// coordinates (x y z) into `coordinates` and true, or false for a point beyond the grid (or
/// not finite).
inline bool cellOf(const float point[3], const float origin[3], float cell, const int size[3],
                   int coordinates[3]) {
  // floor(offset) is in [0, size) exactly when offset is, and is then its truncation: no
  // floor needed (on the baseline x86-64 it is a dozen instructions and a branch).
  for (int axis = 0; axis < 3; ++axis) {
    const float offset = (point[axis] - origin[axis]) / cell;
    if (!(offset >= 0.0f && offset < static_cast<float>(size[axis]))) {
      return false;
    }
    coordinates[axis] = static_cast<int>(offset);
  }
  return true;
}

/// The index of the cell at `coordinates` (x y z) in a grid of `size` cells, x fastest.
inline std::size_t cellIndex(const int coordinates[3], const int size[3]) {
  return (static_cast<std::size_t>(coordinates[2]) * size[1] + coordinates[1]) * size[0] +
         coordinates[0];
}

/// Items sorted by cell: the items of cell c are order[start[c]] .. order[start[c + 1] - 1],
/// in the order they were given.
struct CellLists {
  std::vector<std::uint32_t> start;  ///< one per cell, and the end
  std::vector<std::uint32_t> order;  ///< item indices, cell by cell
};

/// A counting sort of items into `cells` cells, cell_of[i] being item i's cell.
inline CellLists sortIntoCells(const std::vector<std::size_t>& cell_of, std::size_t cells) {
  CellLists lists;
  lists.start.assign(cells + 1, 0);
  for (const std::size_t cell : cell_of) {
    ++lists.start[cell + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) {
    lists.start[c + 1] += lists.start[c];
  }
  std::vector<std::uint32_t> next(lists.start.begin(), lists.start.end() - 1);
  lists.order.resize(cell_of.size());
  for (std::size_t i = 0; i < cell_of.size(); ++i) {
    lists.order[next[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  }
  return lists;
}

}  // namespace granular
