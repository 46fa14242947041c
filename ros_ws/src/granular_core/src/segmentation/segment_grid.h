// ObjectSegmenter's grid: a frame's candidate points on a square grid centred on the sensor,
// grouped by occupied cell, with each cell's highest return. The links, the gates and the
// walls (object_segmentation.cpp) read what it builds. Internal to the segmentation layer.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "granular_core/segmentation/object_segmentation.h"

namespace granular {
namespace segmentation_detail {

// A square grid of `side` x `side` cells of edge `size` centred on the sensor; cell
// row * side + col covers x in [-half + col * size, ...), y likewise with row.
struct PlaneGrid {
  double size = 0.0;
  double half = 0.0;
  int side = 0;

  PlaneGrid(double cell_size, double half_extent)
      : size(cell_size),
        half(half_extent),
        side(static_cast<int>(std::ceil(2.0 * half_extent / cell_size - 1e-9))) {}

  std::size_t cells() const { return static_cast<std::size_t>(side) * side; }
  // The cell of (x, y), or nullopt outside the grid.
  std::optional<std::size_t> cellOf(double x, double y) const {
    // The cast floors what the test lets through (none negative): std::floor was two
    // rounding sequences per candidate return of a frame.
    const double col = (x + half) / size;
    const double row = (y + half) / size;
    if (!(col >= 0.0 && row >= 0.0 && col < side && row < side)) {
      return std::nullopt;
    }
    return static_cast<std::size_t>(row) * side + static_cast<std::size_t>(col);
  }
  double centre(int index) const { return -half + (index + 0.5) * size; }
};

// A bit per cell of a PlaneGrid, rows padded to whole 64-bit words: which cells hold a slot.
class CellBits {
 public:
  // Over `words`, sized (and zeroed) for a grid of `side` x `side` when it is not already.
  CellBits(std::vector<std::uint64_t>& words, int side)
      : words_(words), side_(side), per_row_((static_cast<std::size_t>(side) + 63) / 64) {
    if (words_.size() != per_row_ * static_cast<std::size_t>(side)) {
      words_.assign(per_row_ * static_cast<std::size_t>(side), 0);
    }
  }
  void set(std::uint32_t cell) { words_[wordOf(cell)] |= bitOf(cell); }
  void clear(std::uint32_t cell) { words_[wordOf(cell)] &= ~bitOf(cell); }
  // visit(col) for each set cell of `row` in columns [first, last], ascending.
  template <typename Visit>
  void forEachSet(int row, int first, int last, Visit&& visit) const {
    if (first > last) {
      return;
    }
    const std::uint64_t* row_words = words_.data() + static_cast<std::size_t>(row) * per_row_;
    for (int word = first / 64; word <= last / 64; ++word) {
      const int base = word * 64;
      std::uint64_t bits = row_words[word];
      if (first > base) {
        bits &= ~std::uint64_t{0} << (first - base);
      }
      if (last - base < 63) {
        bits &= ~std::uint64_t{0} >> (63 - (last - base));
      }
      while (bits != 0) {
        visit(base + __builtin_ctzll(bits));
        bits &= bits - 1;
      }
    }
  }

 private:
  std::size_t wordOf(std::uint32_t cell) const {
    return (cell / static_cast<std::uint32_t>(side_)) * per_row_ +
           (cell % static_cast<std::uint32_t>(side_)) / 64;
  }
  std::uint64_t bitOf(std::uint32_t cell) const {
    return std::uint64_t{1} << ((cell % static_cast<std::uint32_t>(side_)) % 64);
  }

  std::vector<std::uint64_t>& words_;
  int side_;
  std::size_t per_row_;
};

// One frame's occupied cells, numbered k in row-major order of their grid cells (so that
// segments come in a fixed order).
struct FrameGrid {
  std::vector<std::uint32_t> occupied;  ///< the grid cell of cell k
  /// The candidates of cell k are by_cell[start[k] .. start[k + 1]), in cloud order.
  std::vector<std::uint32_t> start;
  std::vector<std::size_t> by_cell;
  /// m above the ground: the highest return over cell k, its candidates' and the overhangs'
  /// above it (0 when all lie lower).
  std::vector<float> top_of_cell;
  /// 1 where all of cell k's candidates lie below link_min_top, else 0 (a byte, not a
  /// vector<bool>: the links read it for every pair of cells they look at).
  std::vector<std::uint8_t> low;
  std::vector<Eigen::Vector2d> centre;  ///< of cell k's grid cell
  std::vector<double> range;            ///< m, of that centre from the sensor
};

// The candidates of `cloud` on `grid`: points above the ground (`ground`, the cloud's), at most
// config.max_height high, not the sensor's own vehicle (within config.min_range and
// own_half_width of its x axis), within config.max_range of the sensor (seen from above) and on
// the grid; points higher than max_height but below 8 m are overhangs, which only raise
// top_of_cell. Each occupied cell's place k is written into
// slot[cell] and its bit set in `held` (slot -1 and no bit elsewhere, as given): the caller
// resets both for the next frame.
FrameGrid buildFrameGrid(const Cloud& cloud, const GroundEstimate& ground,
                         const ObjectSegmentationConfig& config, const PlaneGrid& grid,
                         std::vector<std::int32_t>& slot, CellBits& held);

}  // namespace segmentation_detail
}  // namespace granular
