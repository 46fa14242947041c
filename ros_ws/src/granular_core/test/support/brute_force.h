// Brute-force answers the search structures are checked against.
#pragma once

#include <algorithm>
#include <vector>

#include "granular_core/point_types.h"

namespace granular {
namespace testing_support {

// The points as x y z floats, as NearestGrid and NearestPoints take them.
inline std::vector<float> xyzOf(const ModelCloud& cloud) {
  std::vector<float> xyz;
  for (const pcl::PointXYZ& p : cloud.points) {
    xyz.insert(xyz.end(), {p.x, p.y, p.z});
  }
  return xyz;
}

// Brute force with FLANN's L2_Simple order of operations.
inline float bruteNearest(const std::vector<float>& points, const float* query, float bound) {
  float best = bound;
  for (std::size_t i = 0; i < points.size() / 3; ++i) {
    float d = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
      const float step = query[axis] - points[3 * i + axis];
      d += step * step;
    }
    best = std::min(best, d);
  }
  return best;
}

}  // namespace testing_support
}  // namespace granular
