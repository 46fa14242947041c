// The road plane (ground_plane.cpp): RANSAC over the seeds, then least squares on cell means.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "granular_core/ground/ground.h"
#include "support/tilted_road.h"

namespace granular {
namespace {
using testing_support::kDeg;
using testing_support::TiltedRoadTest;

double angleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) / kDeg;
}

TEST_F(TiltedRoadTest, ThePlaneIsFoundWithinATenthOfADegree) {
  GroundPlaneConfig config;
  config.sensor_height = kSensorHeight;
  config.seed_half_fov_deg = 180.0;
  std::size_t seeds = 0, inliers = 0;
  const GroundPlane plane = estimateGroundPlane(cloud_, config, &seeds, &inliers);
  EXPECT_LT(angleDeg(plane.normal, normal_), 0.1);
  EXPECT_NEAR(plane.zUnderSensor(), -kSensorHeight / normal_.z(), 0.01);
  EXPECT_GT(inliers, seeds / 2);
  EXPECT_NEAR(plane.tiltDeg(), angleDeg(normal_, Eigen::Vector3d::UnitZ()), 0.1);
}

TEST_F(TiltedRoadTest, TheSameCloudGivesTheSamePlaneToTheBit) {
  GroundPlaneConfig config;
  config.sensor_height = kSensorHeight;
  const GroundPlane first = estimateGroundPlane(cloud_, config);
  const GroundPlane second = estimateGroundPlane(cloud_, config);
  EXPECT_EQ(first.normal, second.normal);
  EXPECT_EQ(first.offset, second.offset);
}

TEST_F(TiltedRoadTest, SeedsComeOnlyFromTheFieldOfViewAhead) {
  // Only the road behind the sensor: no seed within 40 degrees of +x, the flat plane.
  Cloud behind;
  for (std::size_t i = 0; i < road_end_; ++i) {
    if (cloud_[i].x < 0.0f) {
      behind.push_back(cloud_[i]);
    }
  }
  GroundPlaneConfig config;
  config.sensor_height = kSensorHeight;
  config.seed_half_fov_deg = 40.0;
  std::size_t seeds = 1, inliers = 1;
  GroundPlane plane = estimateGroundPlane(behind, config, &seeds, &inliers);
  EXPECT_EQ(seeds, 0u);
  EXPECT_EQ(inliers, 0u);
  EXPECT_EQ(plane.normal, Eigen::Vector3d::UnitZ());
  config.seed_half_fov_deg = 180.0;
  plane = estimateGroundPlane(behind, config, &seeds, &inliers);
  EXPECT_GT(inliers, 0u);
  EXPECT_LT(angleDeg(plane.normal, normal_), 0.1);
}

TEST(GroundTest, AFlatCloudWithoutRoadGivesTheFlatPlaneBelowTheSensor) {
  Cloud cloud;
  for (int i = 0; i < 50; ++i) {
    cloud.push_back(PointXYZIT(10.0f + i, 0.0f, 5.0f, 0, 0.0));  // all above the seed band
  }
  GroundPlaneConfig config;
  config.sensor_height = 2.3;
  std::size_t seeds = 7, inliers = 7;
  const GroundPlane plane = estimateGroundPlane(cloud, config, &seeds, &inliers);
  EXPECT_EQ(seeds, 0u);
  EXPECT_EQ(inliers, 0u);
  EXPECT_EQ(plane.normal, Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(plane.zUnderSensor(), -2.3);
}

}  // namespace
}  // namespace granular
