#include "granular_core/search/nearest_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "granular_core/search/nearest_points.h"
#include "granular_core/search/grid_cells.h"

namespace granular {
namespace {

// At most this many cells, whatever the cloud's extent (the cell size grows instead).
constexpr double kMaxCells = 4.0e6;
// Cells are sized for about this many points each if the points filled the bounding box;
// surface clouds leave most cells empty and a few points in the others.
constexpr double kPointsPerCellVolume = 0.125;

}  // namespace

NearestGrid::NearestGrid(const float* xyz, std::size_t count, int max_rings)
    : max_rings_(std::max(0, max_rings)) {
  if (count == 0) {
    cell_start_.assign(1, 0);
    return;
  }
  float low[3];
  float high[3];
  boxOfPoints(xyz, count, low, high);
  // A flat or thin cloud still gets a volume, so that the cell size stays sensible.
  double volume = 1.0;
  double longest = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    volume *= std::max(static_cast<double>(high[axis] - low[axis]), 0.01);
    longest = std::max(longest, static_cast<double>(high[axis] - low[axis]));
  }
  double cell = std::cbrt(volume * kPointsPerCellVolume / static_cast<double>(count));
  cell = std::max({cell, cbrt(volume / kMaxCells), longest / 1.0e4, 1.0e-4});
  cell_ = static_cast<float>(cell);
  for (int axis = 0; axis < 3; ++axis) {
    origin_[axis] = low[axis];
    size_[axis] = static_cast<int>((high[axis] - low[axis]) / cell_) + 1;
  }

  const auto cellOf = [&](const float* point) {
    std::size_t index = 0;
    for (int axis = 2; axis >= 0; --axis) {
      const int coordinate = std::min(
          size_[axis] - 1, static_cast<int>((point[axis] - origin_[axis]) / cell_));
      index = index * static_cast<std::size_t>(size_[axis]) + static_cast<std::size_t>(coordinate);
    }
    return index;
  };
  const std::size_t cells = static_cast<std::size_t>(size_[0]) * size_[1] * size_[2];
  std::vector<std::size_t> cell_of(count);
  for (std::size_t i = 0; i < count; ++i) {
    cell_of[i] = cellOf(&xyz[3 * i]);
  }
  CellLists lists = sortIntoCells(cell_of, cells);
  cell_start_ = std::move(lists.start);
  indices_ = std::move(lists.order);
  points_.resize(3 * count);
  for (std::size_t slot = 0; slot < count; ++slot) {
    std::copy(&xyz[3 * indices_[slot]], &xyz[3 * indices_[slot]] + 3, &points_[3 * slot]);
  }
  // The cells within max_rings rings of a point: a query elsewhere cannot be settled here.
  near_.assign(cells, 0);
  for (std::size_t cell = 0; cell < cells; ++cell) {
    if (cell_start_[cell] == cell_start_[cell + 1]) {
      continue;
    }
    const int coordinates[3] = {static_cast<int>(cell % size_[0]),
                                static_cast<int>(cell / size_[0] % size_[1]),
                                static_cast<int>(cell / size_[0] / size_[1])};
    int low[3], high[3];
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = coordinates[axis] - max_rings_;
      high[axis] = coordinates[axis] + max_rings_;
    }
    forEachCell(low, high, size_, [this](std::size_t around) { near_[around] = 1; });
  }
}

void NearestGrid::scan(std::size_t cell, const float query[3], Result& result) const {
  for (std::uint32_t p = cell_start_[cell]; p < cell_start_[cell + 1]; ++p) {
    result.offer(indices_[p], flannSquaredDistance(query, &points_[3 * p]));
  }
}

NearestGrid::Result NearestGrid::nearest(const float query[3], float bound) const {
  Result result;
  result.distance = bound;
  if (indices_.empty()) {
    result.resolved = true;
    return result;
  }
  // The query's cell, which may lie outside the grid, and how far the query is inside it.
  int centre[3];
  float margin = std::numeric_limits<float>::infinity();
  bool inside = true;
  for (int axis = 0; axis < 3; ++axis) {
    const float offset = (query[axis] - origin_[axis]) / cell_;
    const float floor = std::floor(offset);
    centre[axis] = static_cast<int>(std::clamp(floor, -1.0e6f, 1.0e6f));
    margin = std::min({margin, (offset - floor) * cell_, (floor + 1.0f - offset) * cell_});
    inside = inside && centre[axis] >= 0 && centre[axis] < size_[axis];
  }
  // The query's own cell, or none beyond the grid.
  const std::size_t own = inside ? cellIndex(centre, size_) : cell_start_.size();
  bool beyond_rings = inside && near_[own] == 0;
  for (int axis = 0; axis < 3; ++axis) {
    beyond_rings = beyond_rings || centre[axis] < -max_rings_ ||
                   centre[axis] >= size_[axis] + max_rings_;
  }
  if (beyond_rings) {
    // Every point lies more than max_rings cells away along some axis.
    const float reach = (margin + static_cast<float>(max_rings_) * cell_) * 0.9999f;
    result.resolved = bound <= reach * reach;
    return result;
  }
  if (inside) {
    scan(own, query, result);
  }
  // Every point of another cell lies at least `margin` away (less a margin for the rounding
  // of the cell coordinates).
  const float own_reach = margin * 0.9999f;
  if (result.distance <= own_reach * own_reach) {
    result.resolved = true;
    return result;
  }
  // A point nearer than the best so far lies in a cell that the ball of that radius overlaps
  // (widened by 0.1 mm for the rounding of cell coordinates): when the ball stays within the
  // rings, those cells and no others settle the query. Most queries near the model end here.
  const float reach = std::sqrt(result.distance) * 1.0001f + 1.0e-4f;
  if (reach <= static_cast<float>(max_rings_) * cell_) {
    int low[3], high[3];
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = static_cast<int>(std::floor((query[axis] - reach - origin_[axis]) / cell_));
      high[axis] = static_cast<int>(std::floor((query[axis] + reach - origin_[axis]) / cell_));
    }
    forEachCell(low, high, size_, [&](std::size_t cell) {
      if (cell != own) {
        scan(cell, query, result);
      }
    });
    result.resolved = true;
    return result;
  }
  // Otherwise ring by ring, nearest first, until the best seen is nearer than any unseen cell.
  for (int ring = 1; ring <= max_rings_; ++ring) {
    const int z_low = std::max(centre[2] - ring, 0);
    const int z_high = std::min(centre[2] + ring, size_[2] - 1);
    const int y_low = std::max(centre[1] - ring, 0);
    const int y_high = std::min(centre[1] + ring, size_[1] - 1);
    for (int z = z_low; z <= z_high; ++z) {
      for (int y = y_low; y <= y_high; ++y) {
        // Inside the ring's shell only its two x faces, unless y or z is on the shell.
        const bool shell = std::abs(z - centre[2]) == ring || std::abs(y - centre[1]) == ring;
        const int step = shell ? 1 : 2 * ring;
        for (int x = centre[0] - ring; x <= centre[0] + ring; x += step) {
          if (x >= 0 && x < size_[0]) {
            const int cell[3] = {x, y, z};
            scan(cellIndex(cell, size_), query, result);
          }
        }
      }
    }
    const float ring_reach = (margin + static_cast<float>(ring) * cell_) * 0.9999f;
    if (result.distance <= ring_reach * ring_reach) {
      result.resolved = true;
      return result;
    }
  }
  return result;
}

}  // namespace granular
