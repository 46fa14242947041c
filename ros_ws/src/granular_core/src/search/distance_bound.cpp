#include "granular_core/search/distance_bound.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "granular_core/search/grid_cells.h"

namespace granular {
namespace {

// FLANN's float squared distances may lie a few units in the last place off the exact ones
// (relative 1e-6 at most), both the cells' and the queries': the bound gives up that much, and
// a micrometre for the arithmetic in between.
constexpr double kRelativeSlack = 1.0e-5;
constexpr double kAbsoluteSlack = 1.0e-6;  // m

// The centre of cell `index` along one axis, computed the same way wherever it is used.
inline float cellCentre(float origin, int index, float cell) {
  return origin + (static_cast<float>(index) + 0.5f) * cell;
}

}  // namespace

DistanceBound::DistanceBound(const float* xyz, std::size_t count, const NearestPoints& tree,
                             float cell, float margin)
    : cell_(cell) {
  if (count == 0) {
    throw std::invalid_argument("DistanceBound: no points");
  }
  if (!(cell > 0.0f) || !(margin >= 0.0f)) {
    throw std::invalid_argument(
        "DistanceBound: the cell must be positive, the margin not negative");
  }
  boxOfPoints(xyz, count, box_.low, box_.high);
  for (int axis = 0; axis < 3; ++axis) {
    origin_[axis] = box_.low[axis] - margin;
    const float span = box_.high[axis] - box_.low[axis] + 2.0f * margin;
    size_[axis] = static_cast<int>(std::ceil(span / cell)) + 1;
  }
  centre_distance_.resize(static_cast<std::size_t>(size_[0]) * size_[1] * size_[2]);
  std::size_t c = 0;  // x fastest, as cellIndex
  for (int z = 0; z < size_[2]; ++z) {
    for (int y = 0; y < size_[1]; ++y) {
      for (int x = 0; x < size_[0]; ++x, ++c) {
        const float centre[3] = {cellCentre(origin_[0], x, cell), cellCentre(origin_[1], y, cell),
                                 cellCentre(origin_[2], z, cell)};
        centre_distance_[c] = std::sqrt(tree.nearest(centre).distance);
      }
    }
  }
}

float DistanceBound::squaredLowerBound(const float query[3]) const {
  // The box's bound needs no slack: boxDistance never exceeds FLANN's distance to a point in it.
  float bound = boxDistance(query, box_);
  int coordinates[3];
  if (cellOf(query, origin_, cell_, size_, coordinates)) {
    double from_centre = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
      const double d =
          static_cast<double>(query[axis]) - cellCentre(origin_[axis], coordinates[axis], cell_);
      from_centre += d * d;
    }
    const double centre = centre_distance_[cellIndex(coordinates, size_)];
    const double beyond =
        centre * (1.0 - kRelativeSlack) - std::sqrt(from_centre) - kAbsoluteSlack;
    if (beyond > 0.0) {
      bound = std::max(bound, static_cast<float>(beyond * beyond * (1.0 - kRelativeSlack)));
    }
  }
  return bound;
}

}  // namespace granular
