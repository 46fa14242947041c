// NearestPoints: four queries at a time, each with its exact distance.
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/search/nearest_points.h"
#include "support/brute_force.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::boxSurface;
using testing_support::bruteNearest;
using testing_support::xyzOf;

TEST(NearestSearchTest, APacketOfQueriesGetsEachQuerysExactDistance) {
  std::mt19937 random(11);
  const ModelCloud surface = boxSurface({4.5, 1.8, 1.5}, 3000, random);
  const std::vector<float> points = xyzOf(surface);
  const NearestPoints tree(points.data(), surface.size());
  constexpr int kPacket = NearestPoints::kPacket;
  std::uniform_real_distribution<float> centre(-12.0f, 12.0f);
  std::uniform_real_distribution<float> spread(-0.3f, 0.3f);
  for (int packet = 0; packet < 500; ++packet) {
    // Neighbouring queries, as a scan gives, and now and then one from elsewhere.
    const float around[3] = {centre(random), centre(random), centre(random) / 4.0f};
    float queries[kPacket][3];
    float bounds[kPacket];
    for (int lane = 0; lane < kPacket; ++lane) {
      for (int axis = 0; axis < 3; ++axis) {
        queries[lane][axis] = lane == 3 && packet % 5 == 0 ? centre(random)
                                                           : around[axis] + spread(random);
      }
      const float choices[] = {std::numeric_limits<float>::infinity(), 0.01f, 4.0f, 60.0f};
      bounds[lane] = choices[(packet + lane) % 4];
    }
    float distances[kPacket];
    tree.nearestDistances(queries, bounds, distances);
    for (int lane = 0; lane < kPacket; ++lane) {
      // Bit for bit the nearest distance, or the bound when no point lies within it.
      EXPECT_EQ(distances[lane], bruteNearest(points, queries[lane], bounds[lane]))
          << packet << " " << lane;
    }
  }
}

}  // namespace
}  // namespace granular
