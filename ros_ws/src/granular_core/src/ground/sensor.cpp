#include "granular_core/ground/sensor.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <utility>

namespace granular {
namespace {

constexpr double kDegPerRad = 57.29577951308232;

double medianOf(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

// The plane under the sensor without assuming its height: the seed band is placed over the
// cloud's lowest returns instead of under an assumed mounting height.
std::optional<double> groundHeight(const Cloud& cloud, GroundConfig ground,
                                   const SensorEstimateConfig& config) {
  std::vector<double> z;
  for (const PointXYZIT& p : cloud) {
    const double range = std::hypot(p.x, p.y);
    if (std::isfinite(range) && std::isfinite(p.z) && range >= config.min_range &&
        range <= ground.plane.seed_max_range) {
      z.push_back(p.z);
    }
  }
  if (z.empty()) {
    return std::nullopt;
  }
  const auto low = z.begin() + static_cast<std::ptrdiff_t>(
                                   (z.size() - 1) * config.low_percentile / 100.0);
  std::nth_element(z.begin(), low, z.end());
  ground.plane.sensor_height = std::max(0.01, -*low);
  std::size_t inliers = 0;
  const GroundPlane plane = estimateGroundPlane(cloud, ground.plane, nullptr, &inliers);
  if (inliers == 0) {
    return std::nullopt;
  }
  return plane.heightOf(Eigen::Vector3d::Zero());
}

// Angles between consecutive returns of the same ring, in one cloud, added to `histogram`.
std::size_t addRingSteps(const Cloud& cloud, const SensorEstimateConfig& config,
                         std::vector<std::uint32_t>& histogram) {
  std::vector<std::pair<std::int64_t, double>> returns;  // (elevation cell, azimuth deg)
  returns.reserve(cloud.size());
  for (const PointXYZIT& p : cloud) {
    const double range = std::hypot(p.x, p.y);
    if (!std::isfinite(range) || !std::isfinite(p.z) || range < config.min_range ||
        range > config.max_range) {
      continue;
    }
    const double elevation = std::atan2(p.z, range) * kDegPerRad;
    returns.emplace_back(static_cast<std::int64_t>(std::floor(elevation / config.elevation_cell_deg)),
                         std::atan2(p.y, p.x) * kDegPerRad);
  }
  std::sort(returns.begin(), returns.end());
  std::size_t pairs = 0;
  for (std::size_t i = 1; i < returns.size(); ++i) {
    if (returns[i].first != returns[i - 1].first) {
      continue;
    }
    const double step = returns[i].second - returns[i - 1].second;
    if (step <= 0.0 || step >= config.max_step_deg) {
      continue;
    }
    ++histogram[static_cast<std::size_t>(step / config.step_resolution_deg)];
    ++pairs;
  }
  return pairs;
}

}  // namespace

void validate(const SensorConfig& config) {
  config::validateFields(config);
  config::require(config.min_elevation_deg < config.max_elevation_deg,
                  "min_elevation_deg must be below max_elevation_deg");
  config::require(config.min_range < config.max_range, "min_range must be below max_range");
}

SensorEstimate estimateSensor(const std::vector<Cloud>& clouds, const GroundConfig& ground,
                              const SensorEstimateConfig& config) {
  validate(ground);
  config::validateFields(config);
  SensorEstimate estimate;
  estimate.clouds = clouds.size();
  std::vector<double> heights;
  std::vector<std::uint32_t> histogram(
      static_cast<std::size_t>(config.max_step_deg / config.step_resolution_deg) + 1, 0);
  std::size_t pairs = 0;
  for (const Cloud& cloud : clouds) {
    if (const std::optional<double> height = groundHeight(cloud, ground, config)) {
      heights.push_back(*height);
    }
    pairs += addRingSteps(cloud, config, histogram);
  }
  if (!heights.empty()) {
    estimate.mount_height = medianOf(heights);
  } else {
    estimate.problems.push_back(
        "no ground in view: no cloud held a road plane for the mounting height");
  }
  if (pairs >= config.min_pairs) {
    // The commonest angle; its neighbours' counts weigh the bin's centre so that a step
    // that falls between two bins is not rounded to either.
    const auto peak = std::max_element(histogram.begin(), histogram.end()) - histogram.begin();
    double weight = 0.0, sum = 0.0;
    for (std::ptrdiff_t b = std::max<std::ptrdiff_t>(0, peak - 1);
         b <= std::min<std::ptrdiff_t>(static_cast<std::ptrdiff_t>(histogram.size()) - 1,
                                       peak + 1);
         ++b) {
      weight += histogram[static_cast<std::size_t>(b)];
      sum += histogram[static_cast<std::size_t>(b)] * (static_cast<double>(b) + 0.5);
    }
    estimate.azimuth_step_deg = sum / weight * config.step_resolution_deg;
  } else {
    estimate.problems.push_back("no ring structure: " + std::to_string(pairs) +
                                " pairs of returns along a ring, under " +
                                std::to_string(config.min_pairs));
  }
  return estimate;
}

}  // namespace granular
