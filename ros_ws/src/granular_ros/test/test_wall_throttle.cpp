// The nodes' warnings at most once a period on the wall clock, the first at once.
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "granular_ros/wall_throttle.h"

namespace {

TEST(WallThrottleTest, TheFirstWarningGoesOutAtOnceAndTheNextAfterAPeriod) {
  granular_ros::WallThrottle throttle(std::chrono::milliseconds(200));
  EXPECT_TRUE(throttle.due());
  EXPECT_FALSE(throttle.due());
  std::this_thread::sleep_for(std::chrono::milliseconds(250));
  EXPECT_TRUE(throttle.due());
  EXPECT_FALSE(throttle.due());
}

TEST(WallThrottleTest, TwoThrottlesKeepTheirOwnPeriods) {
  granular_ros::WallThrottle clouds, ground;
  EXPECT_TRUE(clouds.due());
  EXPECT_TRUE(ground.due());
  EXPECT_FALSE(clouds.due());
}

}  // namespace
