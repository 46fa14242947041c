// NearestGrid, the kd-tree it falls back on, and BoundedGrid: the exact nearest distance,
// FLANN's to the bit.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/search/bounded_grid.h"
#include "granular_core/search/nearest_grid.h"
#include "granular_core/search/nearest_points.h"
#include "support/brute_force.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::boxSurface;
using testing_support::bruteNearest;
using testing_support::xyzOf;

TEST(NearestSearchTest, GridAndTreeFindTheExactNearestDistance) {
  std::mt19937 random(7);
  const ModelCloud surface = boxSurface({4.5, 1.8, 1.5}, 3000, random);
  const std::vector<float> points = xyzOf(surface);
  const NearestGrid grid(points.data(), surface.size(), 2);
  const NearestPoints tree(points.data(), surface.size());
  std::uniform_real_distribution<float> near(-3.0f, 3.0f);
  std::uniform_real_distribution<float> far(-20.0f, 20.0f);
  int resolved = 0;
  for (int i = 0; i < 4000; ++i) {
    auto& distribution = i % 4 == 0 ? far : near;
    const float query[3] = {distribution(random), distribution(random), distribution(random)};
    for (const float bound : {std::numeric_limits<float>::infinity(), 0.01f, 0.5f}) {
      const float expected = bruteNearest(points, query, bound);
      const NearestPoints::Result exact = tree.nearest(query, bound);
      EXPECT_EQ(exact.found, expected < bound);
      EXPECT_EQ(exact.distance, expected);  // bit for bit
      if (exact.found) {
        const float* p = &points[3 * exact.index];
        EXPECT_EQ(bruteNearest({p[0], p[1], p[2]}, query, bound), expected);
      }
      const NearestGrid::Result cell = grid.nearest(query, bound);
      if (cell.resolved) {
        ++resolved;
        EXPECT_EQ(cell.found, expected < bound);
        EXPECT_EQ(cell.distance, expected);
      } else {
        EXPECT_GE(cell.distance, expected);  // the best seen is an upper bound
      }
    }
  }
  EXPECT_GT(resolved, 2000);  // the grid settles most queries near the cloud
}

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

}  // namespace
}  // namespace granular
