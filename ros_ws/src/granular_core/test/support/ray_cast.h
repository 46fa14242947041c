// A scan cast ray by ray: a flat road below the sensor and axis-aligned blocks on it, opaque or
// a volume that rays may pass through, for the tests of what a scan's rays tell.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "granular_core/point_types.h"

namespace granular {
namespace testing_support {

// An axis-aligned box in the sensor frame.
struct Block {
  Eigen::Vector3d low, high;
  /// Per metre inside it, the chance of a return (0: opaque, its faces return every ray).
  double density = 0.0;
};

// Where the ray `direction` from the origin enters and leaves `block`, if it meets it.
inline std::optional<std::pair<double, double>> crossing(const Eigen::Vector3d& direction,
                                                         const Block& block) {
  double enter = 0.0, leave = 1e9;
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(direction[axis]) < 1e-12) {
      if (0.0 < block.low[axis] || 0.0 > block.high[axis]) {
        return std::nullopt;
      }
      continue;
    }
    double a = block.low[axis] / direction[axis], b = block.high[axis] / direction[axis];
    if (a > b) {
      std::swap(a, b);
    }
    enter = std::max(enter, a);
    leave = std::min(leave, b);
  }
  if (enter >= leave) {
    return std::nullopt;
  }
  return std::make_pair(enter, leave);
}

// The sensor's rings and its step along them.
struct RayCastSensor {
  double height = 1.73;            // m above the road
  double azimuth_step_deg = 0.2;   // between returns along a ring
  double half_fov_deg = 60.0;      // azimuths either side of +x
};

// A 64-ring scan (-24.9 to 2 degrees) of a flat road `sensor.height` below the sensor and
// `blocks`, out to 80 m. A volume returns a ray at a random free path inside it, or lets it
// through to what lies behind.
inline Cloud rayCastScan(const std::vector<Block>& blocks, const RayCastSensor& sensor = {},
                         unsigned seed = 1) {
  constexpr double kDeg = M_PI / 180.0;
  std::mt19937 random(seed);
  Cloud cloud;
  for (int ring = 0; ring < 64; ++ring) {
    const double elevation = (-24.9 + ring * 26.9 / 63.0) * kDeg;
    for (double azimuth = -sensor.half_fov_deg; azimuth <= sensor.half_fov_deg;
         azimuth += sensor.azimuth_step_deg) {
      const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth * kDeg),
                                      std::cos(elevation) * std::sin(azimuth * kDeg),
                                      std::sin(elevation));
      double range = direction.z() < 0.0 ? -sensor.height / direction.z() : 1e9;
      for (const Block& block : blocks) {
        if (const auto through = crossing(direction, block)) {
          const double hit =
              block.density > 0.0
                  ? through->first +
                        std::exponential_distribution<double>(block.density)(random)
                  : through->first;
          if (hit < through->second || block.density == 0.0) {
            range = std::min(range, hit);
          }
        }
      }
      if (range > 80.0) {
        continue;
      }
      const Eigen::Vector3d p = direction * range;
      cloud.push_back(PointXYZIT(float(p.x()), float(p.y()), float(p.z()), 0.0f, 0.0));
    }
  }
  return cloud;
}

}  // namespace testing_support
}  // namespace granular
