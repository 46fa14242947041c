// Convex hulls and minimum-area rectangles of footprints.
#include <cmath>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "granular_core/geometry/footprint.h"

namespace granular {
namespace {

std::vector<Eigen::Vector2d> rectanglePoints(const Eigen::Vector2d& centre, double yaw,
                                             double length, double width, double step) {
  const Eigen::Rotation2Dd rotation(yaw);
  std::vector<Eigen::Vector2d> points;
  for (double u = -length / 2; u <= length / 2 + 1e-9; u += step) {
    for (double v = -width / 2; v <= width / 2 + 1e-9; v += step) {
      points.push_back(centre + rotation * Eigen::Vector2d(u, v));
    }
  }
  return points;
}

TEST(ConvexHullTest, KeepsTheCornersCounterClockwiseAndDropsTheRest) {
  const std::vector<Eigen::Vector2d> hull =
      convexHull({{0, 0}, {2, 0}, {1, 0}, {2, 2}, {0, 2}, {1, 1}, {0.5, 1.5}});
  ASSERT_EQ(hull.size(), 4u);
  EXPECT_EQ(hull[0], Eigen::Vector2d(0, 0));
  EXPECT_EQ(hull[1], Eigen::Vector2d(2, 0));
  EXPECT_EQ(hull[2], Eigen::Vector2d(2, 2));
  EXPECT_EQ(hull[3], Eigen::Vector2d(0, 2));
}

TEST(MinimumAreaRectangleTest, RecoversARotatedRectangle) {
  for (const double yaw : {0.0, 0.3, -1.2, M_PI / 2}) {
    SCOPED_TRACE("yaw " + std::to_string(yaw));
    const Rectangle found =
        minimumAreaRectangle(rectanglePoints({5.0, -3.0}, yaw, 4.4, 1.8, 0.1));
    EXPECT_NEAR(found.length, 4.4, 1e-9);
    EXPECT_NEAR(found.width, 1.8, 1e-9);
    EXPECT_NEAR(found.centre.x(), 5.0, 1e-9);
    EXPECT_NEAR(found.centre.y(), -3.0, 1e-9);
    // An axis: yaw and yaw + pi are the same rectangle.
    EXPECT_NEAR(std::remainder(found.yaw - yaw, M_PI), 0.0, 1e-9);
  }
}

TEST(MinimumAreaRectangleTest, AnLShapedViewGetsTheRectangleOfItsTwoFaces) {
  // The rear and the left side of a car seen from behind and left: two faces, no inside.
  std::vector<Eigen::Vector2d> points;
  for (double u = 0.0; u <= 4.0 + 1e-9; u += 0.05) {
    points.emplace_back(u, 0.0);  // the side, along x
  }
  for (double v = 0.0; v <= 1.8 + 1e-9; v += 0.05) {
    points.emplace_back(0.0, v);  // the rear, along y
  }
  const Rectangle found = minimumAreaRectangle(points);
  EXPECT_NEAR(found.length, 4.0, 1e-9);
  EXPECT_NEAR(found.width, 1.8, 1e-9);
  EXPECT_NEAR(found.yaw, 0.0, 1e-9);
  EXPECT_NEAR(found.centre.x(), 2.0, 1e-9);
  EXPECT_NEAR(found.centre.y(), 0.9, 1e-9);
}

TEST(MinimumAreaRectangleTest, DegenerateInputGivesASegmentOrAPoint) {
  EXPECT_EQ(minimumAreaRectangle({}).length, 0.0);
  const Rectangle point = minimumAreaRectangle({{1, 1}, {1, 1}});
  EXPECT_EQ(point.length, 0.0);
  EXPECT_EQ(point.centre, Eigen::Vector2d(1, 1));
  const Rectangle line = minimumAreaRectangle({{0, 0}, {3, 4}});
  EXPECT_NEAR(line.length, 5.0, 1e-12);
  EXPECT_NEAR(line.width, 0.0, 1e-12);
  EXPECT_NEAR(line.yaw, std::atan2(4.0, 3.0), 1e-12);
}

}  // namespace
}  // namespace granular
