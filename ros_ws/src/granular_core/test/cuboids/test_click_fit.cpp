// A new box where a user clicked (label_cuboids): the road under the click, the clicked object
// apart from its neighbours, its geometric fit with the clicked class's size, and the class's
// size where there is nothing to fit.
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/cuboids/click_fit.h"
#include "support/visible_faces.h"

namespace granular {
namespace {

using testing_support::seenFaces;
using testing_support::StandingBox;

constexpr double kRoad = -1.73;  // z of the road in the sensor frame
constexpr double kDeg = M_PI / 180.0;
const SizePrior kCar{4.5, 1.8, 1.5};

// A frame: the faces of `boxes` the sensor (at the origin) sees, every 0.1 m, on a road at
// kRoad sampled around them, with a few returns below the road, as mirrors give.
std::vector<Eigen::Vector3d> frame(const std::vector<StandingBox>& boxes) {
  std::vector<Eigen::Vector3d> cloud;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> across(-10.0, 10.0);
  for (const StandingBox& box : boxes) {
    for (const Eigen::Vector3d& point : seenFaces(box, Eigen::Vector3d(0, 0, -kRoad), 0.1)) {
      cloud.push_back(point + Eigen::Vector3d(0, 0, kRoad));
    }
    for (int i = 0; i < 3000; ++i) {
      cloud.emplace_back(box.centre.x() + across(random), box.centre.y() + across(random),
                         i % 100 == 0 ? kRoad - 0.8 : kRoad);
    }
  }
  return cloud;
}

// A point of `box`'s face nearest the sensor, half way up, where a user would click.
Eigen::Vector3d clickOnNearFace(const StandingBox& box) {
  const Eigen::Vector2d towards_sensor = -box.centre.normalized();
  const Eigen::Vector2d on_face = box.centre + towards_sensor * 0.8;
  return Eigen::Vector3d(on_face.x(), on_face.y(), kRoad + 0.8);
}

double headingErrorDeg(const OrientedBox& box, double yaw) {
  return std::abs(std::remainder(box.yaw() - yaw, M_PI)) / kDeg;
}

TEST(ClickFitTest, ACarSeenOnTwoSidesGetsItsBox) {
  const StandingBox car{{12.0, -4.0}, 10 * kDeg, {4.5, 1.8, 1.5}};
  const ClickedCuboid clicked =
      fitCuboidAtClick(frame({car}), clickOnNearFace(car), "Car", kCar, CuboidConfig());
  EXPECT_NEAR(clicked.ground, kRoad, 1e-9) << "the low returns below the road do not count";
  EXPECT_EQ(clicked.cuboid.label, "Car");
  EXPECT_GT(clicked.cuboid.points, 100u);
  const OrientedBox& box = clicked.cuboid.box;
  EXPECT_LT((box.centre().head<2>() - car.centre).norm(), 0.1);
  EXPECT_LT(headingErrorDeg(box, car.yaw), 1.0);
  EXPECT_NEAR(box.size().x(), 4.5, 0.12);
  EXPECT_NEAR(box.size().y(), 1.8, 0.12);
  EXPECT_NEAR(box.centre().z() - box.size().z() / 2, kRoad, 1e-6) << "it stands on the road";
}

TEST(ClickFitTest, ACarSeenFromBehindGrowsAwayFromTheSensorKeepingItsRear) {
  const StandingBox car{{12.0, 0.0}, 0.0, {4.5, 1.8, 1.5}};
  const ClickedCuboid clicked =
      fitCuboidAtClick(frame({car}), clickOnNearFace(car), "Car", kCar, CuboidConfig());
  const OrientedBox& box = clicked.cuboid.box;
  EXPECT_LT(headingErrorDeg(box, 0.0), 1.0) << "the rear is its width, not its length";
  EXPECT_NEAR(box.size().x(), 4.5, 0.12);
  EXPECT_NEAR(box.size().y(), 1.8, 0.12);
  EXPECT_NEAR(box.centre().x() - box.size().x() / 2, 12.0 - 2.25, 0.05) << "the rear stays";
}

TEST(ClickFitTest, ANeighbourBeyondTheGapIsNotPartOfTheObject) {
  const StandingBox car{{12.0, -4.0}, 0.0, {4.5, 1.8, 1.5}};
  const StandingBox wall{{12.0, -7.0}, 0.0, {12.0, 0.2, 2.5}};  // 2 m beside the car
  const ClickedCuboid clicked =
      fitCuboidAtClick(frame({car, wall}), clickOnNearFace(car), "Car", kCar, CuboidConfig());
  EXPECT_NEAR(clicked.cuboid.box.size().y(), 1.8, 0.12);
  EXPECT_NEAR(clicked.cuboid.box.size().x(), 4.5, 0.12);
  EXPECT_LT((clicked.cuboid.box.centre().head<2>() - car.centre).norm(), 0.1);
}

TEST(ClickFitTest, TooFewPointsGiveTheClassSizeOnTheRoadAtTheClick) {
  const StandingBox far_car{{30.0, 0.0}, 0.0, {4.5, 1.8, 1.5}};
  const SizePrior pedestrian{0.8, 0.6, 1.75};
  const ClickedCuboid clicked = fitCuboidAtClick(
      frame({far_car}), Eigen::Vector3d(20.0, 3.0, kRoad), "Pedestrian", pedestrian,
      CuboidConfig());
  EXPECT_EQ(clicked.cuboid.points, 0u);
  EXPECT_EQ(clicked.cuboid.label, "Pedestrian");
  const OrientedBox& box = clicked.cuboid.box;
  EXPECT_EQ(box.size(), Eigen::Vector3d(0.8, 0.6, 1.75));
  EXPECT_EQ(box.centre().head<2>(), Eigen::Vector2d(20.0, 3.0));
  EXPECT_NEAR(box.centre().z(), kRoad + 1.75 / 2, 1e-9);
  EXPECT_NEAR(box.yaw(), 0.0, 1e-12);
}

// A box needs the road under the click: without a point within click.ground_radius its height
// would be the click's own (rviz's grid, z = 0, puts it at the sensor's height). Refused, naming
// the click; a click that is not finite too.
TEST(ClickFitTest, AClickAwayFromTheCloudOrNotFiniteIsRefusedNamingIt) {
  const auto refusal = [](const std::vector<Eigen::Vector3d>& cloud, const Eigen::Vector3d& click) {
    try {
      fitCuboidAtClick(cloud, click, "Car", kCar, CuboidConfig());
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("no refusal");
  };
  const StandingBox car{{12.0, 0.0}, 0.0, {4.5, 1.8, 1.5}};
  EXPECT_EQ(refusal({}, Eigen::Vector3d(5.0, 1.0, -1.0)),
            "the cloud has no finite point: nothing to fit a box to");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(refusal({Eigen::Vector3d(nan, 0.0, 0.0)}, Eigen::Vector3d(5.0, 1.0, -1.0)),
            "the cloud has no finite point: nothing to fit a box to");
  EXPECT_EQ(refusal(frame({car}), Eigen::Vector3d(nan, 0.0, 0.0)),
            "the click (nan, 0, 0) is not finite: no box");
  const std::string far = refusal(frame({car}), Eigen::Vector3d(1e6, 0.0, 0.0));
  EXPECT_EQ(far.find("the click (1e+06, 0, 0) is "), 0u) << far;
  EXPECT_NE(far.find(" m from the nearest point of the cloud, farther than click.ground_radius "
                     "(6.0 m): click on the cloud"),
            std::string::npos)
      << far;
}

TEST(ClickFitTest, BadSettingsAreRefused) {
  CuboidConfig config;
  config.click.gap = 0.0;
  EXPECT_THROW(fitCuboidAtClick({}, Eigen::Vector3d::Zero(), "Car", kCar, config),
               std::invalid_argument);
}

}  // namespace
}  // namespace granular
