// Footprints seen from above: their corners, the area two convex polygons share and the
// overlap of two boxes over the smaller one.
#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "granular_core/geometry/overlap.h"

namespace granular {
namespace {

OrientedBox flatBox(double x, double y, double yaw, double length, double width) {
  return OrientedBox(Eigen::Vector3d(x, y, 1.0),
                     Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
                     Eigen::Vector3d(length, width, 1.5));
}

TEST(OverlapTest, FootprintCornersFollowTheYawCounterClockwise) {
  const std::vector<Eigen::Vector2d> corners = footprintCorners(flatBox(1, 2, M_PI / 2, 4, 2));
  ASSERT_EQ(corners.size(), 4u);
  // Length along y, width along x, starting at the rear right.
  EXPECT_NEAR((corners[0] - Eigen::Vector2d(2, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((corners[1] - Eigen::Vector2d(2, 4)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((corners[2] - Eigen::Vector2d(0, 4)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((corners[3] - Eigen::Vector2d(0, 0)).norm(), 0.0, 1e-12);
}

TEST(OverlapTest, SharedAreaOfConvexPolygons) {
  const std::vector<Eigen::Vector2d> square = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  const std::vector<Eigen::Vector2d> shifted = {{1, 1}, {3, 1}, {3, 3}, {1, 3}};
  const std::vector<Eigen::Vector2d> apart = {{5, 5}, {6, 5}, {6, 6}};
  // The square turned by 45 degrees about its centre: an octagon of area 8 (sqrt 2 - 1).
  std::vector<Eigen::Vector2d> diamond;
  for (int k = 0; k < 4; ++k) {
    const double angle = k * M_PI / 2;
    diamond.push_back(Eigen::Vector2d(1, 1) + std::sqrt(2.0) * Eigen::Vector2d(std::cos(angle),
                                                                               std::sin(angle)));
  }
  EXPECT_NEAR(convexOverlapArea(square, square), 4.0, 1e-12);
  EXPECT_NEAR(convexOverlapArea(square, shifted), 1.0, 1e-12);
  EXPECT_NEAR(convexOverlapArea(shifted, square), 1.0, 1e-12);
  EXPECT_EQ(convexOverlapArea(square, apart), 0.0);
  EXPECT_NEAR(convexOverlapArea(square, diamond), 8.0 * (std::sqrt(2.0) - 1.0), 1e-12);
  EXPECT_EQ(convexOverlapArea(square, {{0, 0}, {1, 1}}), 0.0);
}

TEST(OverlapTest, BirdEyeOverlapIsTheSharedAreaOverTheSmallerFootprint) {
  const OrientedBox car = flatBox(0, 0, 0.0, 4, 2);
  EXPECT_NEAR(birdEyeOverlap(car, car), 1.0, 1e-12);
  // Turned by 90 degrees about the same centre: a 2 x 2 square of the 8 m^2.
  EXPECT_NEAR(birdEyeOverlap(car, flatBox(0, 0, M_PI / 2, 4, 2)), 0.5, 1e-12);
  // Half a length ahead: 2 x 2 shared.
  EXPECT_NEAR(birdEyeOverlap(car, flatBox(2, 0, 0.0, 4, 2)), 0.5, 1e-12);
  // A rear seen alone (1 x 2) inside the whole car: fully.
  EXPECT_NEAR(birdEyeOverlap(flatBox(-1.5, 0, 0.0, 1, 2), car), 1.0, 1e-12);
  // Side by side in the next lane: no overlap at all.
  EXPECT_EQ(birdEyeOverlap(car, flatBox(0, 2.1, 0.0, 4, 2)), 0.0);
  // Front and back are the same footprint.
  EXPECT_NEAR(birdEyeOverlap(car, flatBox(0, 0, M_PI, 4, 2)), 1.0, 1e-12);
}

}  // namespace
}  // namespace granular
