// FreeSpace: where a scan's rays passed at a vehicle's body height without a return.
#include <cmath>

#include <gtest/gtest.h>

#include "granular_core/cuboids/free_space.h"

namespace granular {
namespace {

constexpr double kSensorHeight = 1.73;
constexpr double kDeg = M_PI / 180.0;

// The road 1.73 m under the sensor.
GroundPlane flatRoad() {
  GroundPlane plane;
  plane.offset = kSensorHeight;
  return plane;
}

void add(Cloud& cloud, double range, double azimuth_deg, double height) {
  cloud.push_back(PointXYZIT(float(range * std::cos(azimuth_deg * kDeg)),
                             float(range * std::sin(azimuth_deg * kDeg)),
                             float(height - kSensorHeight), 0.0f, 0.0));
}

Eigen::Vector3d at(double range, double azimuth_deg) {
  return {range * std::cos(azimuth_deg * kDeg), range * std::sin(azimuth_deg * kDeg), -1.0};
}

TEST(FreeSpaceTest, RaysAreSeenEmptyUpToTheFirstReturnInTheBodyBand) {
  Cloud cloud;
  add(cloud, 10.0, 0.0, 1.0);  // a wall straight ahead, 10 m away
  add(cloud, 30.0, 0.0, 0.0);  // the road beyond it
  add(cloud, 30.0, 90.0, 0.0);  // the road alone, to the left
  const FreeSpace space(cloud, flatRoad(), FreeSpaceConfig());
  EXPECT_TRUE(space.seenEmpty(at(9.5, 0.0)));
  EXPECT_FALSE(space.seenEmpty(at(10.5, 0.0)));  // behind the wall
  // The ray to the road 30 m away left the band (0.5 m above the road) at
  // 30 * (1.73 - 0.5) / 1.73 = 21.33 m.
  EXPECT_TRUE(space.seenEmpty(at(21.2, 90.0)));
  EXPECT_FALSE(space.seenEmpty(at(21.5, 90.0)));
  // No return at all: nothing is known.
  EXPECT_FALSE(space.seenEmpty(at(5.0, -90.0)));
}

TEST(FreeSpaceTest, ReturnsAboveTheBandNeitherBlockNorClear) {
  Cloud cloud;
  add(cloud, 8.0, 45.0, 3.0);  // a crown over the road
  const FreeSpace space(cloud, flatRoad(), FreeSpaceConfig());
  EXPECT_FALSE(space.seenEmpty(at(4.0, 45.0)));
  add(cloud, 20.0, 45.0, 0.0);
  const FreeSpace with_road(cloud, flatRoad(), FreeSpaceConfig());
  EXPECT_TRUE(with_road.seenEmpty(at(12.0, 45.0)));
}

TEST(FreeSpaceTest, AReturnInTheBandOccupiesItsCell) {
  Cloud cloud;
  add(cloud, 10.1, 0.0, 1.0);   // a car's side straight ahead
  add(cloud, 12.1, 0.0, 1.2);   // another behind it: returned, so something stands there too
  add(cloud, 8.0, 90.0, 0.1);   // the road
  add(cloud, 8.0, -90.0, 3.0);  // a crown
  const FreeSpace space(cloud, flatRoad(), FreeSpaceConfig());  // 0.2 m cells
  EXPECT_TRUE(space.seenOccupied(at(10.1, 0.0)));
  EXPECT_TRUE(space.seenOccupied(at(12.1, 0.0)));
  EXPECT_FALSE(space.seenOccupied(at(10.5, 0.0)));
  EXPECT_FALSE(space.seenOccupied(at(8.0, 90.0)));
  EXPECT_FALSE(space.seenOccupied(at(8.0, -90.0)));
  FreeSpaceConfig no_cells;
  no_cells.occupied_cell = 0.0;
  EXPECT_FALSE(FreeSpace(cloud, flatRoad(), no_cells).seenOccupied(at(10.1, 0.0)));
}

TEST(FreeSpaceTest, AZeroBinWidthKnowsNothing) {
  Cloud cloud;
  add(cloud, 30.0, 0.0, 0.0);
  FreeSpaceConfig config;
  config.bin_deg = 0.0;
  EXPECT_FALSE(FreeSpace(cloud, flatRoad(), config).seenEmpty(at(5.0, 0.0)));
}

}  // namespace
}  // namespace granular
