// fitSegmentCuboids: a frame's segments cut, fitted and judged the one way fit_cuboids and the
// segment_cloud node do it, on a scan cast ray by ray.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "granular_core/cuboids/frame_cuboids.h"
#include "support/ray_cast.h"

namespace granular {
namespace {

using testing_support::Block;

// A 64-ring sensor 1.73 m above the road, a return every 0.2 degrees along its rings (KITTI's
// HDL-64E, nearly).
const testing_support::RayCastSensor kSensor{1.73, 0.2, 60.0};

// A car (4.5 x 1.8 m) with its length along y from `y`, its side turned to the sensor at
// x = kRange: its body up to 1 m and a cabin over its middle up to 1.5 m.
constexpr double kRange = 12.0;

std::vector<Block> car(double y) {
  const double road = -kSensor.height;
  return {{{kRange, y, road}, {kRange + 1.8, y + 4.5, road + 1.0}, 0.0},
          {{kRange + 0.15, y + 1.2, road + 1.0}, {kRange + 1.65, y + 3.4, road + 1.5}, 0.0}};
}

// Two cars parked nose to tail across the line of sight, 0.5 m between the boot of one and the
// bonnet of the other, and the segmentation that joined them: one segment of every return
// above the road, on the flat road.
struct Scene {
  Cloud cloud;
  ObjectSegmentation segmentation;
};

Scene twoTouchingCars() {
  std::vector<Block> blocks = car(-4.75);
  const std::vector<Block> second = car(0.25);
  blocks.insert(blocks.end(), second.begin(), second.end());
  Scene scene;
  scene.cloud = testing_support::rayCastScan(blocks, kSensor);
  scene.segmentation.ground.plane.offset = kSensor.height;
  std::vector<std::size_t> above_road;
  for (std::size_t i = 0; i < scene.cloud.size(); ++i) {
    if (scene.cloud[i].z > -kSensor.height + 0.05) {
      above_road.push_back(i);
    }
  }
  scene.segmentation.segments.push_back(
      {OrientedBox(Eigen::Vector3d(kRange + 0.9, 0.0, -kSensor.height + 0.75),
                   Eigen::Quaterniond::Identity(), Eigen::Vector3d(1.8, 9.5, 1.5)),
       above_road});
  return scene;
}

SegmentationStageConfig segmentation() {
  SegmentationStageConfig config;
  config.objects.azimuth_step_deg = kSensor.azimuth_step_deg;
  return config;
}

CuboidConfig cuboids() {
  CuboidConfig config;
  config.geometric.classes = {"Sedan", "SUV", "Hatchback", "Jeep", "BoxTruck", "SchoolBus"};
  return config;
}

TEST(FrameCuboidsTest, TwoTouchingCarsHalfAMetreApartAreTwoCuboids) {
  const Scene scene = twoTouchingCars();
  const CuboidConfig config = cuboids();
  const auto fitter = makeCuboidFitter(config, {});
  const FrameCuboids result =
      fitSegmentCuboids(scene.cloud, scene.segmentation, segmentation(), config, *fitter, 1);
  ASSERT_EQ(result.kept.size(), 2u);
  EXPECT_EQ(result.fitted_objects, 2u);
  EXPECT_EQ(result.milliseconds.size(), 2u);
  EXPECT_TRUE(result.not_vehicles.empty());
  EXPECT_EQ(result.without_cuboid, 0u);
  // One car each, in the segment's order: the first keeps the segment's id, the piece cut
  // off takes the first id after the frame's segments.
  const double centres[2] = {-2.5, 2.5};
  for (std::size_t car = 0; car < 2; ++car) {
    const FrameCuboid& kept = result.kept[car];
    EXPECT_EQ(kept.id, static_cast<std::int64_t>(car));
    EXPECT_EQ(kept.object, 0u);
    const OrientedBox& box = kept.cuboid.box;
    EXPECT_NEAR(box.centre().x(), kRange + 0.9, 0.1);
    EXPECT_NEAR(box.centre().y(), centres[car], 0.1);
    EXPECT_NEAR(std::max(box.size().x(), box.size().y()), 4.5, 0.1);
    EXPECT_NEAR(std::min(box.size().x(), box.size().y()), 1.8, 0.1);
  }
}

TEST(FrameCuboidsTest, WithoutTheVehicleDecisionNothingIsCutOrDropped) {
  const Scene scene = twoTouchingCars();
  CuboidConfig config = cuboids();
  config.evidence.enabled = false;
  const auto fitter = makeCuboidFitter(config, {});
  const FrameCuboids result =
      fitSegmentCuboids(scene.cloud, scene.segmentation, segmentation(), config, *fitter, 1);
  ASSERT_EQ(result.kept.size(), 1u);
  EXPECT_EQ(result.kept[0].id, 0);
  const Eigen::Vector3d& size = result.kept[0].cuboid.box.size();
  EXPECT_NEAR(std::max(size.x(), size.y()), 9.5, 0.1);  // both cars in one box
}

// A fitted car at (x, y) heading `yaw_deg`, its heading seen or left open.
std::optional<FittedCuboid> fittedCar(double x, double y, double yaw_deg, bool heading_seen) {
  const OrientedBox box(Eigen::Vector3d(x, y, -1.0),
                       Eigen::Quaterniond(Eigen::AngleAxisd(yaw_deg * M_PI / 180.0,
                                                            Eigen::Vector3d::UnitZ())),
                       Eigen::Vector3d(4.5, 1.8, 1.5));
  const FittedCuboid cuboid{kUnknownLabel, 1.0, box, 100, heading_seen};
  return cuboid;
}

// A row of three cars parked side by side, headings seen along x, and a fourth at the row's
// end whose points left its heading open and whose fit turned it across the row.
std::vector<std::optional<FittedCuboid>> rowWithAnOpenCar() {
  return {fittedCar(12.0, -2.6, 1.0, true), fittedCar(12.0, 0.0, -2.0, true),
          fittedCar(12.2, 2.6, 179.0, true), fittedCar(12.0, 5.2, 88.0, false)};
}

TEST(FrameCuboidsTest, ACarWhoseHeadingWasLeftOpenTakesItsRowsHeading) {
  const std::vector<std::optional<double>> lent =
      lentHeadings(rowWithAnOpenCar(), {true, true, true, true}, NeighbourHeadingConfig());
  ASSERT_EQ(lent.size(), 4u);
  EXPECT_FALSE(lent[0] || lent[1] || lent[2]);  // seen: nothing lent
  ASSERT_TRUE(lent[3]);
  EXPECT_NEAR(std::abs(std::remainder(*lent[3], M_PI)), 0.0, 2.5 * M_PI / 180.0);
}

TEST(FrameCuboidsTest, NoHeadingIsLentWithoutTwoNeighboursThatAgree) {
  NeighbourHeadingConfig config;
  std::vector<std::optional<FittedCuboid>> cars = rowWithAnOpenCar();
  // One seen neighbour within the radius: the nearest alone may be a merged pair.
  config.radius = 3.0;
  EXPECT_FALSE(lentHeadings(cars, {true, true, true, true}, config)[3]);
  // Two of three within the radius are not vehicles.
  EXPECT_FALSE(lentHeadings(cars, {false, true, false, true}, NeighbourHeadingConfig())[3]);
  // The neighbours disagree: two along the row, two across it.
  cars.push_back(fittedCar(9.0, 4.0, 90.0, true));
  cars.push_back(fittedCar(9.0, 7.0, 92.0, true));
  EXPECT_FALSE(lentHeadings(cars, std::vector<bool>(6, true), NeighbourHeadingConfig())[3]);
  // A fit within min_turn_deg of its row's heading keeps its own.
  cars = rowWithAnOpenCar();
  cars[3] = fittedCar(12.0, 5.2, 15.0, false);
  EXPECT_FALSE(lentHeadings(cars, {true, true, true, true}, NeighbourHeadingConfig())[3]);
}

TEST(FrameCuboidsTest, ObjectsWithoutACuboidAreCountedNotKept) {
  FrameObject empty;
  empty.id = 7;
  const CuboidConfig config = cuboids();
  const auto fitter = makeCuboidFitter(config, {});
  const FrameCuboids result = fitFrameObjects({empty}, *fitter, FrameCuboidsOptions());
  EXPECT_TRUE(result.kept.empty());
  EXPECT_EQ(result.fitted_objects, 1u);
  EXPECT_EQ(result.without_cuboid, 1u);
}

}  // namespace
}  // namespace granular
