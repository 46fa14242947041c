// PolarReturns: a frame's finite returns about the sensor, for the free space and the decision.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "granular_core/cuboids/polar_returns.h"
#include "granular_core/geometry/fast_atan2.h"

namespace granular {
namespace {

TEST(PolarReturnsTest, EachFiniteReturnHasItsAzimuthRangeAndHeightInCloudOrder) {
  GroundPlane road;  // 1.73 m under the sensor
  road.offset = 1.73;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Cloud cloud;
  cloud.push_back(PointXYZIT(3.0f, 4.0f, -0.73f, 0.0f, 0.0));
  cloud.push_back(PointXYZIT(nan, 1.0f, 0.0f, 0.0f, 0.0));  // no return
  cloud.push_back(PointXYZIT(-2.0f, 0.0f, -1.73f, 0.0f, 0.0));
  const PolarReturns scan(cloud, road);
  ASSERT_EQ(scan.returns().size(), 2u);
  const PolarReturns::Return& first = scan.returns()[0];
  EXPECT_DOUBLE_EQ(first.azimuth, fastAtan2(4.0, 3.0) + M_PI);  // the bins' own azimuth
  EXPECT_DOUBLE_EQ(first.range, 5.0);
  EXPECT_NEAR(first.height, 1.0, 1e-6);
  EXPECT_EQ(first.x, 3.0f);
  EXPECT_EQ(first.y, 4.0f);
  const PolarReturns::Return& second = scan.returns()[1];
  EXPECT_DOUBLE_EQ(second.azimuth, 2.0 * M_PI);  // straight behind: atan2 = pi
  EXPECT_DOUBLE_EQ(second.range, 2.0);
  EXPECT_NEAR(second.height, 0.0, 1e-6);
}

}  // namespace
}  // namespace granular
