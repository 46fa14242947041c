// DistanceBound: never above the exact nearest distance, and close to it where it matters.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/search/distance_bound.h"
#include "granular_core/search/nearest_points.h"
#include "support/brute_force.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::boxSurface;
using testing_support::bruteNearest;
using testing_support::xyzOf;

TEST(DistanceBoundTest, BoundsEveryDistanceFromBelowAndWithinACellsDiagonal) {
  std::mt19937 random(3);
  const ModelCloud surface = boxSurface({4.5, 1.8, 1.5}, 3000, random);
  const std::vector<float> points = xyzOf(surface);
  const NearestPoints tree(points.data(), surface.size());
  constexpr float kCell = 0.2f;
  constexpr float kMargin = 0.5f;
  const DistanceBound bound(points.data(), surface.size(), tree, kCell, kMargin);
  // Queries on the surface, just off it, in the cells' margin and far beyond it.
  std::uniform_real_distribution<float> near(-3.0f, 3.0f);
  std::uniform_real_distribution<float> far(-20.0f, 20.0f);
  std::uniform_real_distribution<float> jitter(-0.01f, 0.01f);
  int within_cells = 0;
  for (int i = 0; i < 4000; ++i) {
    float query[3];
    if (i % 4 == 0) {
      const std::size_t on = static_cast<std::size_t>(i) % surface.size();
      for (int axis = 0; axis < 3; ++axis) {
        query[axis] = points[3 * on + axis] + (i % 8 == 0 ? 0.0f : jitter(random));
      }
    } else {
      for (int axis = 0; axis < 3; ++axis) {
        query[axis] = i % 4 == 3 ? far(random) : near(random);
      }
    }
    const float exact = bruteNearest(points, query, std::numeric_limits<float>::infinity());
    const float lower = bound.squaredLowerBound(query);
    ASSERT_LE(lower, exact) << "query " << query[0] << " " << query[1] << " " << query[2];
    // Inside the cells it gives up at most a cell's diagonal; beyond them the box's distance
    // (which for a box's surface is the distance itself, off its faces).
    // (A little inside: the sampled points may stop short of the box's faces.)
    const float reach = kMargin - 0.05f;
    const bool in_cells = std::abs(query[0]) < 2.25f + reach && std::abs(query[1]) < 0.9f + reach &&
                          query[2] > -reach && query[2] < 1.5f + reach;
    if (in_cells) {
      ++within_cells;
      const float give = std::max(0.0f, std::sqrt(exact) - kCell * std::sqrt(3.0f));
      EXPECT_GE(lower, give * give * 0.999f) << query[0] << " " << query[1] << " " << query[2];
    }
  }
  EXPECT_GT(within_cells, 1000);
}

TEST(DistanceBoundTest, ASinglePointsBoundIsItsDistanceOutsideTheCells) {
  const float point[3] = {1.0f, 2.0f, 3.0f};
  const NearestPoints tree(point, 1);
  const DistanceBound bound(point, 1, tree, 0.2f, 0.5f);
  const float away[3] = {1.0f, 2.0f, 13.0f};  // 10 m above it, beyond the cells
  EXPECT_NEAR(bound.squaredLowerBound(away), 100.0f, 100.0f * 2e-5f);
  EXPECT_LE(bound.squaredLowerBound(away), 100.0f);
  EXPECT_EQ(bound.squaredLowerBound(point), 0.0f);
}

}  // namespace
}  // namespace granular
