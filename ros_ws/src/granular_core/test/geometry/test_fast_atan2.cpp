// fastAtan2: the bins of the vehicle decision take its angle only beyond its error from an edge.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "granular_core/geometry/fast_atan2.h"

namespace granular {
namespace {

TEST(FastAtan2Test, WithinItsStatedErrorAllAroundLargestAtTheDiagonals) {
  double largest = 0.0, where = 0.0;
  for (int step = -1800000; step <= 1800000; ++step) {
    const double angle = step * 1e-6 * M_PI;
    const double y = 7.0 * std::sin(angle), x = 7.0 * std::cos(angle);
    const double error = std::abs(std::remainder(fastAtan2(y, x) - std::atan2(y, x), 2 * M_PI));
    if (error > largest) {
      largest = error;
      where = angle;
    }
  }
  EXPECT_LT(largest, 2.1e-4);
  EXPECT_GT(largest, 2.0e-4);  // the vehicle decision's margin from a bin edge must exceed it
  EXPECT_NEAR(std::abs(std::remainder(where, M_PI / 2)), M_PI / 4, 1e-3);
  EXPECT_EQ(fastAtan2(0.0, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(fastAtan2(0.0, -1.0), M_PI);
}

}  // namespace
}  // namespace granular
