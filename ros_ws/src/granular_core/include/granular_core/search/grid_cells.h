#pragma once

// Uniform 3-D grids of cells stored x fastest, as NearestGrid, NdtMatcher and the point
// histograms' CellIndex keep them (a header of the library's sources, not of its interface).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace granular {

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
