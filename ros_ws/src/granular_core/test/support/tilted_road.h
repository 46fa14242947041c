// A tilted road sampled as a rotating LiDAR sees it, with boxes standing on it: shared by the
// ground stage's tests and the road plane's.
#pragma once

#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "granular_core/point_types.h"

namespace granular {
namespace testing_support {

constexpr double kDeg = M_PI / 180.0;

// A road tilted by `tilt_deg` about the y axis and `roll_deg` about x, `sensor_height` below
// the sensor, sampled as a rotating LiDAR would (rings of constant angle below the horizon),
// with boxes standing on it. Obstacle points lie at least 0.3 m above the road.
class TiltedRoadTest : public ::testing::Test {
 protected:
  static constexpr double kSensorHeight = 1.8;

  void SetUp() override {
    const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(kTiltDeg * kDeg, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(kRollDeg * kDeg, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    normal_ = tilt * Eigen::Vector3d::UnitZ();
    offset_ = kSensorHeight;  // the plane passes kSensorHeight below the sensor along its normal
    std::mt19937 random(7);
    std::uniform_real_distribution<double> jitter(-0.01, 0.01);
    // The road: points on the plane out to 45 m, denser near the sensor as a LiDAR's are.
    for (double range = 3.0; range < 45.0; range *= 1.04) {
      for (double azimuth = -M_PI; azimuth < M_PI; azimuth += 0.5 * kDeg) {
        addOnPlane(range * std::cos(azimuth), range * std::sin(azimuth), 0.0);
      }
    }
    road_end_ = cloud_.size();
    // Obstacles: a car-sized box 12 m ahead, a pillar to the left, a wall behind.
    addBox({12.0, -2.0}, {4.4, 1.8}, 0.3, 1.5, random, jitter);
    addBox({5.0, 8.0}, {0.4, 0.4}, 0.3, 3.0, random, jitter);
    addBox({-15.0, 0.0}, {0.3, 12.0}, 0.3, 2.0, random, jitter);
  }

  void addOnPlane(double x, double y, double height) {
    // The point of the plane above (x, y), then `height` along the normal.
    const double z = -(normal_.x() * x + normal_.y() * y + offset_) / normal_.z();
    const Eigen::Vector3d p = Eigen::Vector3d(x, y, z) + height * normal_;
    cloud_.push_back(PointXYZIT(static_cast<float>(p.x()), static_cast<float>(p.y()),
                                static_cast<float>(p.z()), 0, 0.0));
  }

  template <typename Jitter>
  void addBox(const Eigen::Vector2d& centre, const Eigen::Vector2d& size, double bottom,
              double top, std::mt19937& random, Jitter& jitter) {
    for (double h = bottom; h <= top; h += 0.1) {
      for (double u = -size.x() / 2; u <= size.x() / 2; u += 0.1) {
        for (const double v : {-size.y() / 2, size.y() / 2}) {
          addOnPlane(centre.x() + u + jitter(random), centre.y() + v, h);
          addOnPlane(centre.x() + v * size.x() / size.y(), centre.y() + u * size.y() / size.x(),
                     h);
        }
      }
    }
  }

  static constexpr double kTiltDeg = 3.0;
  static constexpr double kRollDeg = -1.5;
  Eigen::Vector3d normal_;
  double offset_ = 0.0;
  Cloud cloud_;
  std::size_t road_end_ = 0;
};

}  // namespace testing_support
}  // namespace granular
