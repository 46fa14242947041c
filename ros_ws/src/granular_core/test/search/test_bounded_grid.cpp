// BoundedGrid: the exact nearest point within a bound, FLANN's distance and tie-break to the
// bit; none beyond the bound.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/search/bounded_grid.h"
#include "granular_core/search/nearest_points.h"
#include "support/brute_force.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::boxSurface;
using testing_support::bruteNearest;
using testing_support::xyzOf;

TEST(NearestSearchTest, TheBoundedGridAnswersEveryQueryWithinItsBoundExactly) {
  // ICP's 0.05 m, ICP-NL's 0.1 m, the report's 0.01 m, the model fit's 0.5 m and 1 m (cells
  // narrower than the bound there): near the cloud, far from it, beyond the grid, and on points
  // of the cloud itself (distance 0, and ties).
  std::mt19937 random(11);
  ModelCloud surface = boxSurface({4.5, 1.8, 1.5}, 3000, random);
  surface.push_back(surface[10]);  // the same point twice: the lower index wins
  const std::vector<float> points = xyzOf(surface);
  std::uniform_real_distribution<float> near(-3.0f, 3.0f);
  std::uniform_real_distribution<float> far(-20.0f, 20.0f);
  std::normal_distribution<float> jitter(0.0f, 0.03f);
  for (const float radius : {0.01f, 0.05f, 0.1f, 0.5f, 1.0f}) {
    const float bound = radius * radius;
    const BoundedGrid grid(points.data(), surface.size(), bound);
    EXPECT_EQ(grid.bound(), bound);
    int found = 0;
    for (int i = 0; i < 6000; ++i) {
      float query[3];
      if (i % 3 == 0) {
        const float* p = &points[3 * (static_cast<std::size_t>(i) % surface.size())];
        for (int axis = 0; axis < 3; ++axis) {
          query[axis] = p[axis] + (i % 2 == 0 ? jitter(random) : 0.0f);
        }
      } else {
        auto& distribution = i % 3 == 1 ? near : far;
        for (float& coordinate : query) {
          coordinate = distribution(random);
        }
      }
      const float expected = bruteNearest(points, query, bound);
      const NearestGrid::Result result = grid.nearest(query);
      ASSERT_TRUE(result.resolved);
      ASSERT_EQ(result.found, expected < bound) << radius << " " << i;
      if (result.found) {
        ++found;
        EXPECT_EQ(result.distance, expected);  // bit for bit
        // The lowest index at that distance, as FLANN's order gives.
        std::size_t first = 0;
        while (flannSquaredDistance(query, &points[3 * first]) != expected) {
          ++first;
        }
        EXPECT_EQ(result.index, first) << radius << " " << i;
      }
    }
    EXPECT_GE(found, 1000) << radius;  // the 1,000 queries exactly on points find them
  }
  const BoundedGrid empty(nullptr, 0, 0.01f);
  const float query[3] = {0.0f, 0.0f, 0.0f};
  EXPECT_FALSE(empty.nearest(query).found);
}

TEST(BoundedGridTest, ANearestPointJustBeyondTheBoundIsNotFound) {
  const std::vector<float> points = {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f};
  const BoundedGrid grid(points.data(), 2, 0.25f);  // 0.5 m
  const float within[3] = {0.0f, 0.49f, 0.0f};
  const NearestGrid::Result near = grid.nearest(within);
  ASSERT_TRUE(near.found);
  EXPECT_EQ(near.index, 0u);
  EXPECT_EQ(near.distance, 0.49f * 0.49f);
  const float beyond[3] = {0.5f, 0.51f, 0.0f};  // 0.51 m and more from both points
  EXPECT_FALSE(grid.nearest(beyond).found);
  const float between[3] = {0.5f, 0.0f, 0.0f};  // 0.5 m from both: on the bound, not below it
  EXPECT_FALSE(grid.nearest(between).found);
}

}  // namespace
}  // namespace granular
