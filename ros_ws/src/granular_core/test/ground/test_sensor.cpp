// sensor:=auto: a sensor's mounting height and azimuth step measured from its clouds, on a
// synthetic scan and on the KITTI fixture's HDL-64E (1.73 m, 0.176 deg).
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/ground/sensor.h"
#include "support/kitti.h"

namespace granular {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A rotating sensor `height` above a flat road, `rings` lasers from -20 to +5 degrees, a return
// every `step_deg` along each ring, with range noise; a wall 15 m ahead stops the rays there.
Cloud syntheticScan(double height, double step_deg, int rings, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, 0.02);
  Cloud cloud;
  for (int ring = 0; ring < rings; ++ring) {
    const double elevation = (-20.0 + 25.0 * ring / (rings - 1)) * kDeg;
    for (double azimuth = 0.0; azimuth < 360.0; azimuth += step_deg) {
      const double a = azimuth * kDeg;
      double range = elevation < 0.0 ? height / std::tan(-elevation) : 1e9;
      if (std::abs(a) < 0.5 || std::abs(a - 2 * M_PI) < 0.5) {
        range = std::min(range, 15.0 / std::cos(a));  // the wall ahead
      }
      if (range > 80.0) {
        continue;
      }
      range += noise(random);
      cloud.push_back(PointXYZIT(float(range * std::cos(a)), float(range * std::sin(a)),
                                 float(range * std::tan(elevation)), 0.0f, 0.0));
    }
  }
  return cloud;
}

GroundConfig allAround() {
  GroundConfig ground;
  ground.plane.seed_half_fov_deg = 180.0;
  return ground;
}

TEST(SensorEstimateTest, RecoversASyntheticSensorsHeightAndAzimuthStep) {
  for (const auto& [height, step] : std::vector<std::pair<double, double>>{
           {1.9, 0.2}, {2.7, 0.3515625}, {1.2, 1.0}}) {
    SCOPED_TRACE("height " + std::to_string(height) + ", step " + std::to_string(step));
    const std::vector<Cloud> clouds{syntheticScan(height, step, 32, 1),
                                    syntheticScan(height, step, 32, 2)};
    const SensorEstimate estimate = estimateSensor(clouds, allAround());
    ASSERT_TRUE(estimate.mount_height);
    ASSERT_TRUE(estimate.azimuth_step_deg);
    EXPECT_NEAR(*estimate.mount_height, height, 0.05);
    EXPECT_NEAR(*estimate.azimuth_step_deg, step, 0.1 * step);
    EXPECT_TRUE(estimate.problems.empty());
  }
}

TEST(SensorEstimateTest, SaysWhenTheCloudsCannotTell) {
  // Everything above the sensor (a ceiling), scattered at random: no road, no rings.
  std::mt19937 random(3);
  std::uniform_real_distribution<double> spread(-20.0, 20.0);
  Cloud ceiling;
  for (int i = 0; i < 5000; ++i) {
    ceiling.push_back(PointXYZIT(float(spread(random)), float(spread(random)),
                                 float(3.0 + 0.1 * spread(random)), 0.0f, 0.0));
  }
  const SensorEstimate estimate = estimateSensor({ceiling}, allAround());
  EXPECT_FALSE(estimate.mount_height);
  EXPECT_FALSE(estimate.azimuth_step_deg);
  ASSERT_EQ(estimate.problems.size(), 2u);
  EXPECT_NE(estimate.problems[0].find("no ground in view"), std::string::npos);
  EXPECT_NE(estimate.problems[1].find("no ring structure"), std::string::npos);
}

TEST(SensorEstimateTest, KittiFramesGiveTheHdl64eAsMounted) {
  if (!std::filesystem::is_directory(testing_kitti::kFixture)) {
    GTEST_SKIP() << "KITTI fixture not found at " << testing_kitti::kFixture;
  }
  std::vector<Cloud> clouds;
  for (int index = 0; index < 10; ++index) {
    char frame[16];
    std::snprintf(frame, sizeof(frame), "%06d.bin", index);
    clouds.push_back(testing_kitti::readVelodyne(testing_kitti::kFixture / "velodyne" / frame));
  }
  const SensorEstimate estimate = estimateSensor(clouds);
  ASSERT_TRUE(estimate.mount_height);
  ASSERT_TRUE(estimate.azimuth_step_deg);
  std::printf("[ KITTI ] mount height %.3f m, azimuth step %.4f deg\n", *estimate.mount_height,
              *estimate.azimuth_step_deg);
  EXPECT_NEAR(*estimate.mount_height, 1.73, 0.05);
  EXPECT_NEAR(*estimate.azimuth_step_deg, 0.176, 0.0176);
}

}  // namespace
}  // namespace granular
