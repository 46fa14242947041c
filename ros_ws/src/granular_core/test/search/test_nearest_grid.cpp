// NearestGrid and the kd-tree it falls back on: the exact nearest distance, FLANN's to the
// bit.
#include <random>
#include <vector>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace granular
