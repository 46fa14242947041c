// esfFeatures (esf_features.cpp): PCL's Ensemble of Shape Functions, 640 values normalised to
// sum to 1, from the finite points only. PCL seeds its sampling with the time, so two calls
// may differ: the tests assert what holds for any draw.
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/supervised/object_features.h"

namespace granular {
namespace {

// Points on the faces of a 4 x 2 x 1.5 m box.
Cloud boxCloud(std::size_t count) {
  std::mt19937 random(9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Cloud cloud;
  for (std::size_t i = 0; i < count; ++i) {
    const float u = unit(random), v = unit(random);
    switch (i % 3) {
      case 0: cloud.push_back(PointXYZIT(4.0f * u, 0.0f, 1.5f * v, 0, 0.0)); break;
      case 1: cloud.push_back(PointXYZIT(0.0f, 2.0f * u, 1.5f * v, 0, 0.0)); break;
      default: cloud.push_back(PointXYZIT(4.0f * u, 2.0f * v, 1.5f, 0, 0.0)); break;
    }
  }
  return cloud;
}

TEST(EsfFeaturesTest, SixHundredFortyNonNegativeValuesSummingToOne) {
  const std::vector<float> features = esfFeatures(boxCloud(500));
  ASSERT_EQ(features.size(), 640u);
  for (const float value : features) {
    EXPECT_GE(value, 0.0f);
  }
  EXPECT_NEAR(std::accumulate(features.begin(), features.end(), 0.0), 1.0, 1e-4);
  // The D2 "in" histogram (values 384..447) is filled by every object with a surface.
  EXPECT_GT(std::accumulate(features.begin() + 384, features.begin() + 448, 0.0), 0.0);
}

TEST(EsfFeaturesTest, NonFinitePointsAreLeftOutAndFewerThanThreeGiveZeros) {
  Cloud cloud = boxCloud(2);
  cloud.push_back(PointXYZIT(NAN, 1.0f, 1.0f, 0, 0.0));
  cloud.push_back(PointXYZIT(1.0f, INFINITY, 1.0f, 0, 0.0));
  const std::vector<float> features = esfFeatures(cloud);  // two finite points
  EXPECT_EQ(features, std::vector<float>(640, 0.0f));
  EXPECT_EQ(esfFeatures(Cloud()), std::vector<float>(640, 0.0f));

  Cloud with_nan = boxCloud(300);
  with_nan.push_back(PointXYZIT(NAN, NAN, NAN, 0, 0.0));
  const std::vector<float> values = esfFeatures(with_nan);
  for (const float value : values) {
    ASSERT_TRUE(std::isfinite(value));
  }
  EXPECT_NEAR(std::accumulate(values.begin(), values.end(), 0.0), 1.0, 1e-4);
}

}  // namespace
}  // namespace granular
