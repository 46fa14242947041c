// OrientedBox: frames and refusals.
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "granular_core/geometry/oriented_box.h"

namespace granular {
namespace {

Eigen::Quaterniond yawPitchRoll(double yaw, double pitch, double roll) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
         Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

TEST(OrientedBoxTest, YawIsTheHeadingOfTheLengthAxis) {
  const OrientedBox box(Eigen::Vector3d(3, 4, 0), yawPitchRoll(-2.1, 0.3, 0.2),
                        Eigen::Vector3d(1, 1, 1));
  EXPECT_NEAR(box.yaw(), -2.1, 1e-12);
  EXPECT_NEAR(box.range(), 5.0, 1e-12);
}

TEST(OrientedBoxTest, RejectsBadSizeAndQuaternion) {
  const Eigen::Vector3d centre(1, 2, 3);
  const Eigen::Vector3d size(4, 2, 1.5);
  const Eigen::Quaterniond unit = Eigen::Quaterniond::Identity();
  EXPECT_THROW(OrientedBox(centre, unit, Eigen::Vector3d(4, 0, 1.5)), std::invalid_argument);
  EXPECT_THROW(OrientedBox(centre, unit, Eigen::Vector3d(4, -2, 1.5)), std::invalid_argument);
  EXPECT_THROW(OrientedBox(centre, unit, Eigen::Vector3d(4, 2, NAN)), std::invalid_argument);
  EXPECT_THROW(OrientedBox(centre, Eigen::Quaterniond(0, 0, 0, 0), size), std::invalid_argument);
  EXPECT_THROW(OrientedBox(centre, Eigen::Quaterniond(NAN, 0, 0, 1), size),
               std::invalid_argument);
  EXPECT_THROW(OrientedBox(Eigen::Vector3d(INFINITY, 0, 0), unit, size), std::invalid_argument);

  const OrientedBox scaled(centre, Eigen::Quaterniond(0.0, 0.0, 0.0, 3.0), size);
  EXPECT_NEAR(scaled.orientation().norm(), 1.0, 1e-15);
}

}  // namespace
}  // namespace granular
