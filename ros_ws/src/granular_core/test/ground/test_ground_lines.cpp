// Heights above per-sector ground lines: they follow a road that rises where one plane cannot.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/ground/ground.h"

namespace granular {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kSensorHeight = 1.73;

// The road's z at horizontal range r: on the plane under the sensor at 3 m, then rising 0.05 m
// per metre (a slope the lines accept, 0.15 being their most): 1.85 m up at 40 m.
double roadZ(double range) { return -kSensorHeight + 0.05 * (range - 3.0); }

// The road ahead (azimuth -60 to 60 deg), a return every 0.25 m of range out to 40 m.
Cloud risingRoad() {
  Cloud cloud;
  for (double azimuth = -60.0; azimuth <= 60.0; azimuth += 1.0) {
    for (double range = 3.0; range <= 40.0; range += 0.25) {
      cloud.push_back(PointXYZIT(static_cast<float>(range * std::cos(azimuth * kDeg)),
                                 static_cast<float>(range * std::sin(azimuth * kDeg)),
                                 static_cast<float>(roadZ(range)), 0, 0.0));
    }
  }
  return cloud;
}

GroundPlane flatPlane() {
  GroundPlane plane;
  plane.offset = kSensorHeight;  // z = -1.73
  return plane;
}

TEST(GroundLinesTest, TheRoadRisingAwayIsGroundAndWhatStandsOnItKeepsItsHeight) {
  Cloud cloud = risingRoad();
  const std::size_t road = cloud.size();
  // A point 1 m above the risen road 30 m ahead: 2 m above the flat plane.
  cloud.push_back(PointXYZIT(30.0f, 0.0f, static_cast<float>(roadZ(30.0) + 1.0), 0, 0.0));
  const std::vector<float> heights = groundLineHeights(cloud, flatPlane(), GroundLinesConfig());
  ASSERT_EQ(heights.size(), cloud.size());
  float worst = 0.0f;
  for (std::size_t i = 0; i < road; ++i) {
    worst = std::max(worst, std::abs(heights[i]));
  }
  EXPECT_LT(worst, 1e-4f);  // every road return on its sector's line, 37 m of it
  EXPECT_NEAR(heights[road], 1.0f, 0.01f);
}

TEST(GroundLinesTest, ASectorWithoutLinesMeasuresAboveThePlane) {
  Cloud cloud = risingRoad();
  // Behind the sensor, where no road was seen: 1.5 m up is too far off the plane to start a
  // ground line (0.4 m + 0.05 m per metre of range), so its height is above the plane.
  cloud.push_back(PointXYZIT(-10.0f, 0.0f, static_cast<float>(-kSensorHeight + 1.5), 0, 0.0));
  const std::vector<float> heights = groundLineHeights(cloud, flatPlane(), GroundLinesConfig());
  EXPECT_NEAR(heights.back(), 1.5f, 1e-6f);
}

TEST(GroundLinesTest, BeyondMaxRangeAPointKeepsItsHeightAboveThePlane) {
  Cloud cloud = risingRoad();
  GroundLinesConfig config;
  config.max_range = 25.0;
  const std::vector<float> heights = groundLineHeights(cloud, flatPlane(), config);
  // The last return, 40 m ahead: 1.85 m up the rise, measured from the plane.
  EXPECT_NEAR(heights[risingRoad().size() - 1 - 0], roadZ(40.0) + kSensorHeight, 1e-5);
}

TEST(GroundLinesTest, ANonFinitePointHasNoHeight) {
  Cloud cloud = risingRoad();
  cloud.push_back(PointXYZIT(NAN, 0.0f, -1.0f, 0, 0.0));
  const std::vector<float> heights = groundLineHeights(cloud, flatPlane(), GroundLinesConfig());
  EXPECT_TRUE(std::isnan(heights.back()));
}

}  // namespace
}  // namespace granular
