#include "granular_core/search/bounded_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "granular_core/search/grid_cells.h"
#include "granular_core/search/nearest_points.h"

namespace granular {
namespace {

// At most this many cells, whatever the cloud's extent (they grow wider instead).
constexpr double kMaxCells = 4.0e6;
// At most this wide (m), whatever the bound: a list holds the points within the bound of its
// cell, and a query scans those nearer the cell's centre than itself plus its best distance,
// so a wide cell on a dense cloud is a long scan. The model fit's 0.5 m bound in 0.5 m cells:
// p95 9.5-11.8 ms an object; in 0.25 m cells 7.2-7.7 ms, the process's peak memory 1.7 times
// (0.17 m: about 10% faster, 3 times; 0.125 m: no faster, 6 times). ICP's bounds (0.01-0.1 m)
// keep cells as wide as the bound (half as wide made ICP-NL slower).
constexpr double kMaxCell = 0.25;
// Slack (m) for the rounding of cell coordinates: a list holds the points within the bound
// plus this of its cell, so a query that rounds into a neighbouring cell still finds them.
constexpr double kSlack = 1.0e-4;

}  // namespace

BoundedGrid::BoundedGrid(const float* xyz, std::size_t count, float bound)
    : bound_(bound), root_bound_(std::sqrt(bound)) {
  if (count == 0) {
    list_start_.assign(1, 0);
    return;
  }
  const double reach = std::sqrt(static_cast<double>(bound)) + kSlack;
  float box_low[3];
  float box_high[3];
  boxOfPoints(xyz, count, box_low, box_high);
  double low[3] = {box_low[0], box_low[1], box_low[2]};
  double high[3] = {box_high[0], box_high[1], box_high[2]};
  // The grid covers the points and the bound around them: a query beyond has no point near.
  double volume = 1.0;
  for (int axis = 0; axis < 3; ++axis) {
    low[axis] -= reach;
    high[axis] += reach;
    volume *= high[axis] - low[axis];
  }
  cell_ = static_cast<float>(std::max(std::min(reach, kMaxCell), std::cbrt(volume / kMaxCells)));
  for (int axis = 0; axis < 3; ++axis) {
    origin_[axis] = static_cast<float>(low[axis]);
    size_[axis] = static_cast<int>((high[axis] - low[axis]) / cell_) + 1;
  }

  // Each point goes into the list of every cell it lies within `reach` of, per axis.
  const auto cellsNear = [&](const float* point, int first[3], int last[3]) {
    for (int axis = 0; axis < 3; ++axis) {
      const double offset = static_cast<double>(point[axis]) - origin_[axis];
      first[axis] = std::max(0, static_cast<int>(std::floor((offset - reach) / cell_)));
      last[axis] = std::min(size_[axis] - 1, static_cast<int>(std::floor((offset + reach) / cell_)));
    }
  };
  const std::size_t cells = static_cast<std::size_t>(size_[0]) * size_[1] * size_[2];
  std::vector<std::size_t> cell_of;  // per entry, entries in point order
  std::vector<std::uint32_t> point_of;
  cell_of.reserve(27 * count);
  point_of.reserve(27 * count);
  for (std::size_t i = 0; i < count; ++i) {
    int first[3], last[3];
    cellsNear(&xyz[3 * i], first, last);
    forEachCell(first, last, size_, [&](std::size_t cell) {
      cell_of.push_back(cell);
      point_of.push_back(static_cast<std::uint32_t>(i));
    });
  }
  CellLists lists = sortIntoCells(cell_of, cells);
  list_start_ = std::move(lists.start);
  // Each list nearest its cell's centre first, so that a query can stop early (nearest());
  // equal distances keep the point order (the entries' order within a list).
  std::vector<std::pair<float, std::uint32_t>> by_distance;
  indices_.resize(lists.order.size());
  points_.resize(3 * lists.order.size());
  from_centre_.resize(lists.order.size());
  for (std::size_t c = 0; c < cells; ++c) {
    const std::uint32_t begin = list_start_[c], end = list_start_[c + 1];
    if (begin == end) {
      continue;
    }
    const float centre[3] = {
        origin_[0] + cell_ * (static_cast<float>(c % size_[0]) + 0.5f),
        origin_[1] + cell_ * (static_cast<float>(c / size_[0] % size_[1]) + 0.5f),
        origin_[2] + cell_ * (static_cast<float>(c / size_[0] / size_[1]) + 0.5f)};
    by_distance.clear();
    for (std::uint32_t slot = begin; slot < end; ++slot) {
      const std::uint32_t entry = lists.order[slot];
      by_distance.emplace_back(
          std::sqrt(flannSquaredDistance(centre, &xyz[3 * point_of[entry]])), entry);
    }
    std::sort(by_distance.begin(), by_distance.end());
    for (std::uint32_t slot = begin; slot < end; ++slot) {
      const auto& [distance, entry] = by_distance[slot - begin];
      const std::uint32_t point = point_of[entry];
      indices_[slot] = point;
      from_centre_[slot] = distance;
      std::copy(&xyz[3 * point], &xyz[3 * point] + 3, &points_[3 * slot]);
    }
  }
}

NearestGrid::Result BoundedGrid::nearest(const float query[3]) const {
  NearestGrid::Result result;
  result.resolved = true;
  result.distance = bound_;
  int coordinates[3];
  if (!cellOf(query, origin_, cell_, size_, coordinates)) {
    return result;  // beyond the grid (or not finite): no point within the bound
  }
  const std::size_t cell = cellIndex(coordinates, size_);
  float centre[3];
  for (int axis = 0; axis < 3; ++axis) {
    centre[axis] = origin_[axis] + cell_ * (static_cast<float>(coordinates[axis]) + 0.5f);
  }
  // An entry lies at least its distance from the centre less the query's from it: once that
  // exceeds the best distance (widened for rounding), no later entry can be nearer.
  const float query_from_centre = std::sqrt(flannSquaredDistance(centre, query));
  const auto stopAt = [&](float root_distance) {
    return query_from_centre + root_distance * 1.0001f + 1.0e-5f;
  };
  float stop = stopAt(root_bound_);
  for (std::uint32_t entry = list_start_[cell];
       entry < list_start_[cell + 1] && from_centre_[entry] <= stop; ++entry) {
    if (result.offer(indices_[entry], flannSquaredDistance(query, &points_[3 * entry]))) {
      stop = stopAt(std::sqrt(result.distance));
    }
  }
  return result;
}

}  // namespace granular
