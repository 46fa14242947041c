// A detection's points isolated from its neighbours, and the baseline rectangle.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "support/visible_faces.h"

namespace granular {
namespace {

using testing_support::seenFaces;
using testing_support::StandingBox;

constexpr double kDeg = M_PI / 180.0;

// A flat road through the sensor's origin (points are given in the road's frame).
GroundPlane flatRoad() { return GroundPlane(); }

TEST(IsolateObjectTest, KeepsTheClustersMostlyInTheBoxAndDropsTheRoad) {
  StandingBox car, neighbour;
  car.centre = {10.0, 3.0};
  neighbour.centre = {10.0 + 4.5 + 0.8, 3.0};  // parked 0.8 m behind it
  std::vector<Eigen::Vector3d> points = seenFaces(car, Eigen::Vector3d(0, 0, 1.7), 0.05);
  const std::size_t car_points = points.size();
  for (const Eigen::Vector3d& point : seenFaces(neighbour, Eigen::Vector3d(0, 0, 1.7), 0.05)) {
    points.push_back(point);
  }
  for (double x = 7.0; x < 17.0; x += 0.1) {
    points.emplace_back(x, 3.0, 0.05);  // road returns
  }
  // The box as given, its margin taking in the neighbour's nearest metre.
  const std::vector<Eigen::Vector3d> object = isolateObject(
      points, flatRoad(), Eigen::Vector3d(10.0, 3.0, 0.75), car.size, CuboidConfig());
  ASSERT_EQ(object.size(), car_points);
  for (const Eigen::Vector3d& point : object) {
    EXPECT_LE(point.x(), 12.25 + 1e-9);
    EXPECT_GE(point.z(), 0.3);
  }
}

TEST(IsolateObjectTest, TheClusterWithMostPointsInTheCircleWhenNoneIsMostlyIn) {
  // A wall along y = 5 passing by a small box at (10, 5): none of the wall is mostly inside.
  std::vector<Eigen::Vector3d> points;
  for (double x = 0.0; x < 30.0; x += 0.05) {
    points.emplace_back(x, 5.0, 1.0);
  }
  const std::vector<Eigen::Vector3d> object =
      isolateObject(points, flatRoad(), Eigen::Vector3d(10.0, 5.0, 1.0),
                    Eigen::Vector3d(1.0, 1.0, 1.0), CuboidConfig());
  EXPECT_EQ(object.size(), points.size());
  EXPECT_TRUE(isolateObject({}, flatRoad(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(),
                            CuboidConfig())
                  .empty());
}

TEST(RectangleFitTest, TheBaselineBoxesTheSeenPointsOnly) {
  StandingBox car;
  car.centre = {12.0, 0.0};
  car.yaw = 10.0 * kDeg;
  ObjectView object;
  object.ground = GroundPlane();
  object.points = seenFaces(car, Eigen::Vector3d(0, 0, 1.7), 0.05);
  const std::optional<FittedCuboid> fitted = RectangleCuboidFitter(CuboidConfig()).fit(object);
  ASSERT_TRUE(fitted);
  // The rear and the right side are seen: their hull is a right triangle, and the rectangle
  // along its hypotenuse (21.8 deg off) has the same area as the car's outline. Rotating
  // calipers take the first edge of least area, here the hypotenuse: the baseline's L-shapes
  // are often boxed askew.
  EXPECT_NEAR(fitted->box.size().x() * fitted->box.size().y(), 4.5 * 1.8, 1e-6);
  EXPECT_NEAR(std::remainder(fitted->box.yaw() - car.yaw, M_PI), std::atan2(1.8, 4.5), 1e-6);
  EXPECT_EQ(fitted->label, kUnknownLabel);
  // Seen from straight behind, a rear face gives a box 5 cm deep, centred on the rear.
  car.yaw = 0.0;
  object.points = seenFaces(car, Eigen::Vector3d(0, 0, 1.7), 0.05);
  const std::optional<FittedCuboid> rear = RectangleCuboidFitter(CuboidConfig()).fit(object);
  ASSERT_TRUE(rear);
  EXPECT_NEAR(rear->box.centre().x(), 12.0 - 2.25, 0.03);
  EXPECT_NEAR(rear->box.size().x(), 1.8, 1e-6);
}

}  // namespace
}  // namespace granular
