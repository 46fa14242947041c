#include "granular_core/ground/ground.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace granular {

double GroundPlane::tiltDeg() const {
  return std::acos(std::clamp(normal.normalized().z(), -1.0, 1.0)) * 180.0 / M_PI;
}

Eigen::Isometry3d GroundPlane::levelling() const {
  const Eigen::Quaterniond rotation =
      Eigen::Quaterniond::FromTwoVectors(normal.normalized(), Eigen::Vector3d::UnitZ());
  // After the rotation the plane is z = -offset (a point p on it had normal . p = -offset).
  Eigen::Isometry3d levelling = Eigen::Isometry3d::Identity();
  levelling.linear() = rotation.toRotationMatrix();
  levelling.translation() = Eigen::Vector3d(0.0, 0.0, offset);
  return levelling;
}

void validate(const GroundConfig& config) {
  config::validateFields(config);
  config::require(config.plane.seed_min_range < config.plane.seed_max_range,
                  "plane.seed_min_range must be below plane.seed_max_range");
  // The seed and refinement grids cover the seed region, and the lines' bins every sector's
  // range: each in memory at once.
  constexpr double kMaxCellsASide = 4000.0;
  config::require(2.0 * config.plane.seed_max_range / config.plane.seed_cell <= kMaxCellsASide,
                  "2 plane.seed_max_range / plane.seed_cell must be at most 4000 cells a side");
  config::require(2.0 * config.plane.seed_max_range / config.plane.refine_cell <= kMaxCellsASide,
                  "2 plane.seed_max_range / plane.refine_cell must be at most 4000 cells a side");
  config::require(config.lines.sectors * (config.lines.max_range / config.lines.bin_size) <= 1.0e7,
                  "lines.sectors * lines.max_range / lines.bin_size must be at most 1e7 bins");
}

GroundEstimate estimateGround(const Cloud& cloud, const GroundConfig& config) {
  validate(config);
  GroundEstimate estimate;
  estimate.plane = estimateGroundPlane(cloud, config.plane, &estimate.seeds, &estimate.inliers);
  if (config.model == GroundModel::kLines) {
    estimate.heights = groundLineHeights(cloud, estimate.plane, config.lines);
  } else {
    estimate.heights.assign(cloud.size(), std::nanf(""));
    for (std::size_t i = 0; i < cloud.size(); ++i) {
      const PointXYZIT& point = cloud[i];
      if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
        estimate.heights[i] = static_cast<float>(
            estimate.plane.heightOf(Eigen::Vector3d(point.x, point.y, point.z)));
      }
    }
  }
  estimate.ground.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    estimate.ground[i] = estimate.heights[i] < config.ground_height;  // NaN: false
  }
  return estimate;
}

std::optional<std::string> groundNotFound(const Cloud& cloud, std::size_t inliers,
                                          const GroundPlaneConfig& config) {
  if (inliers > 0) {
    return std::nullopt;
  }
  if (cloud.empty()) {
    return std::string("no points, so no ground");
  }
  float lowest = std::numeric_limits<float>::infinity();
  std::size_t finite = 0;
  for (const PointXYZIT& point : cloud.points) {
    if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
      ++finite;
      lowest = std::min(lowest, point.z);
    }
  }
  if (finite == 0) {
    return "all " + std::to_string(cloud.size()) + " points are NaN or infinite, so no ground";
  }
  char text[400];
  std::snprintf(text, sizeof(text),
                "no ground plane found among %zu points (the lowest at z = %.2f m; road is "
                "sought near z = -%.2f m, sensor_height); heights are taken above a flat plane "
                "there: is the cloud in the sensor's frame, sensor_height right, the view not "
                "filled by a wall?",
                finite, lowest, config.sensor_height);
  return std::string(text);
}

}  // namespace granular
