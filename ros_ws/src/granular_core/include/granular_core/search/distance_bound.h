#pragma once

#include <cstddef>
#include <vector>

#include "granular_core/search/nearest_points.h"

namespace granular {

/// A lower bound of the distance from any place to a fixed cloud, in constant time: what lets
/// a fitness score be rejected without its nearest-point searches. A grid of cells over the
/// cloud's box widened by a margin holds the exact distance from each cell's centre to the
/// cloud; by the triangle inequality a query's distance is at least that less its own distance
/// to the centre, and at least its distance to the cloud's box (everywhere, inside the grid or
/// beyond it).
class DistanceBound {
 public:
  /// Over `count` points given as x y z floats (all finite; at least one), indexed by `tree`
  /// (which answers the cells' exact distances), with cells `cell` m wide reaching `margin` m
  /// beyond the points' box.
  DistanceBound(const float* xyz, std::size_t count, const NearestPoints& tree, float cell,
                float margin);

  /// At most the squared distance FLANN's float arithmetic gives from `query` to its nearest
  /// point of the cloud (flannSquaredDistance), m^2. Thread-safe.
  float squaredLowerBound(const float query[3]) const;

 private:
  struct Box {
    float low[3];
    float high[3];
  };
  Box box_;          ///< the points' box
  float origin_[3];  ///< the grid's corner
  float cell_;
  int size_[3] = {0, 0, 0};
  std::vector<float> centre_distance_;  ///< m, per cell, x fastest
};

}  // namespace granular
