#pragma once

// Walking the cells of a uniform 3-D grid stored x fastest, for the grids of NearestGrid and
// NdtMatcher (a header of this folder, not of the library's interface).

#include <algorithm>
#include <cstddef>

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

}  // namespace granular
