#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "granular_core/search/nearest_grid.h"

namespace granular {

/// Exact nearest-point queries within a fixed bound of a fixed cloud: ICP's correspondence
/// search, which discards a nearest point beyond its maximum correspondence distance. A
/// uniform grid of cells as wide as the bound (at most 0.25 m), each listing, one after the
/// other, the points within the bound of any place in the cell, nearest the cell's centre
/// first: a query reads its cell's list, instead of visiting the cells around it, and stops
/// once no later entry can be nearer than the best so far. Distances and ties are
/// NearestGrid's (FLANN's float arithmetic; the lowest index among equals), so the answers are
/// the same to the bit.
class BoundedGrid {
 public:
  /// Indexes `count` points given as x y z floats (all finite) for queries of squared bound
  /// `bound` (m^2, finite and positive).
  BoundedGrid(const float* xyz, std::size_t count, float bound);

  /// The squared bound it was built for: queries within it are answered.
  float bound() const { return bound_; }

  /// The nearest point whose squared distance to `query` is below bound(); always resolved.
  /// Thread-safe.
  NearestGrid::Result nearest(const float query[3]) const;

 private:
  float bound_;
  float root_bound_;  ///< sqrt(bound_), where a query's scan starts from
  float origin_[3] = {0.0f, 0.0f, 0.0f};
  float cell_ = 1.0f;
  int size_[3] = {0, 0, 0};
  std::vector<std::uint32_t> list_start_;  ///< entries of cell c: [list_start_[c], [c + 1])
  std::vector<float> points_;              ///< x y z per entry
  std::vector<std::uint32_t> indices_;     ///< index into the given cloud, per entry
  std::vector<float> from_centre_;         ///< distance of each entry to its cell's centre
};

}  // namespace granular
