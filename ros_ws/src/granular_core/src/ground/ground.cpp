#include "granular_core/ground/ground.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

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
      const double height = estimate.plane.heightOf(Eigen::Vector3d(point.x, point.y, point.z));
      // Finite exactly where x, y and z are (the plane is; 0 times infinity is NaN; no float
      // overflows it): one test for three.
      if (std::isfinite(height)) {
        estimate.heights[i] = static_cast<float>(height);
      }
    }
  }
  estimate.ground.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    estimate.ground[i] = estimate.heights[i] < config.ground_height ? 1 : 0;  // NaN: 0
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

namespace {

// The plane under the lowest returns of `cloud`, wherever they lie and leaning up to
// search_tilt_deg; nullopt when fewer than min_inliers seeds hold one.
std::optional<GroundPlane> planeAnywhere(const Cloud& cloud, const GroundConfig& config) {
  std::vector<float> z;
  for (const PointXYZIT& point : cloud.points) {
    if (std::isfinite(point.x) && std::isfinite(point.y) && std::isfinite(point.z)) {
      z.push_back(point.z);
    }
  }
  if (z.empty()) {
    return std::nullopt;
  }
  // The seed band over the lowest 5 % of the returns, as sensor:=auto places it.
  const auto low = z.begin() + static_cast<std::ptrdiff_t>((z.size() - 1) / 20);
  std::nth_element(z.begin(), low, z.end());
  GroundPlaneConfig search = config.plane;
  search.sensor_height = std::max(0.01, -static_cast<double>(*low));
  search.eps_angle_deg = config.sensor_frame.search_tilt_deg;
  std::size_t inliers = 0;
  const GroundPlane plane = estimateGroundPlane(cloud, search, nullptr, &inliers);
  if (inliers < config.sensor_frame.min_inliers) {
    return std::nullopt;
  }
  return plane;
}

}  // namespace

GroundCheck checkGround(const Cloud& cloud, const GroundPlane& plane, std::size_t inliers,
                        const GroundConfig& config, const std::string& frame_id) {
  const SensorFrameCheckConfig& check = config.sensor_frame;
  // Few or no seeds on the plane found near -sensor_height: the road may lie elsewhere (a
  // world frame's road at z = 0, or one leaning beyond plane.eps_angle_deg).
  const std::optional<GroundPlane> road =
      inliers >= check.min_inliers ? std::optional<GroundPlane>(plane)
                                   : planeAnywhere(cloud, config);
  const auto off = [&](const GroundPlane& found) {
    return std::abs(found.zUnderSensor() + config.plane.sensor_height) > check.height_tolerance ||
           found.tiltDeg() > check.max_tilt_deg;
  };
  if (road && off(*road)) {
    const std::string quoted = "'" + frame_id + "'";
    const std::string frame = frame_id.empty() ? "a frame not recorded" : "frame " + quoted;
    char text[900];
    std::snprintf(
        text, sizeof(text),
        "the road lies at z = %.2f m under the sensor, tilted %.1f deg, where the sensor's "
        "frame has it at z = -%.2f m (sensor_height; within %.2f m, "
        "ground sensor_frame.height_tolerance) and level (within %.1f deg, "
        "sensor_frame.max_tilt_deg): the cloud, in %s, looks like a world or vehicle frame, not "
        "the sensor's. Give clouds in the sensor's frame (a static transform from %s to the "
        "sensor, e.g. tf2_ros static_transform_publisher, and the clouds moved into it), or the "
        "sensor that took them (sensor:=NAME; --sensor NAME, or --sensor auto)",
        // Rounded to the printed centimetre first, so that a road at -0.001 m reads 0.00.
        std::round(road->zUnderSensor() * 100.0) / 100.0 + 0.0, road->tiltDeg(),
        config.plane.sensor_height, check.height_tolerance,
        check.max_tilt_deg, frame.c_str(),
        frame_id.empty() ? "the clouds' frame" : quoted.c_str());
    return {GroundCheck::Verdict::kNotSensorFrame, text};
  }
  if (const auto problem = groundNotFound(cloud, inliers, config.plane)) {
    return {GroundCheck::Verdict::kNotFound, *problem};
  }
  return {};
}

}  // namespace granular
