// A synthetic scan: a flat road seen in rings, and upright boxes standing on it, for the
// tests of the box-free path (segmentation, background, cuboids).
#pragma once

#include <cmath>
#include <set>

#include <Eigen/Geometry>

#include "granular_core/ground/ground.h"
#include "granular_core/point_types.h"

namespace granular {
namespace testing_support {

inline constexpr double kSensorHeight = 1.73;

// Flat road 1.73 m below the sensor out to 40 m, as rings of returns.
inline Cloud road() {
  Cloud cloud;
  for (double range = 3.0; range < 40.0; range *= 1.03) {
    for (double azimuth = -M_PI; azimuth < M_PI; azimuth += 0.4 * M_PI / 180.0) {
      cloud.push_back(PointXYZIT(static_cast<float>(range * std::cos(azimuth)),
                                 static_cast<float>(range * std::sin(azimuth)),
                                 static_cast<float>(-kSensorHeight), 0, 0.0));
    }
  }
  return cloud;
}

// The faces of an upright box standing on the road, sampled every `step` metres from `bottom`
// m above the road (its foot, where the road is in the way of the returns, or higher where the
// sensor saw no more of it) to its top; returns the indices of its points.
inline std::set<std::size_t> addBox(Cloud& cloud, const Eigen::Vector2d& centre, double yaw,
                             const Eigen::Vector3d& size, double step = 0.05,
                             double bottom = 0.3) {
  std::set<std::size_t> added;
  const Eigen::Rotation2Dd rotation(yaw);
  const auto add = [&](double u, double v, double h) {
    const Eigen::Vector2d p = centre + rotation * Eigen::Vector2d(u, v);
    added.insert(cloud.size());
    cloud.push_back(PointXYZIT(static_cast<float>(p.x()), static_cast<float>(p.y()),
                               static_cast<float>(-kSensorHeight + h), 0, 0.0));
  };
  for (double h = bottom; h <= size.z() + 1e-9; h += step) {
    for (double u = -size.x() / 2; u <= size.x() / 2 + 1e-9; u += step) {
      add(u, -size.y() / 2, h);
      add(u, size.y() / 2, h);
    }
    for (double v = -size.y() / 2 + step; v < size.y() / 2 - 1e-9; v += step) {
      add(-size.x() / 2, v, h);
      add(size.x() / 2, v, h);
    }
  }
  return added;
}

// The ground stage for the road: the sensor kSensorHeight above it, seeds all around.
inline GroundConfig roadGround() {
  GroundConfig ground;
  ground.plane.sensor_height = kSensorHeight;
  ground.plane.seed_half_fov_deg = 180.0;
  return ground;
}

}  // namespace testing_support
}  // namespace granular
