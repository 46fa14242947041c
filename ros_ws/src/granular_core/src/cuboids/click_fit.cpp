// A new box where a user clicked (label_cuboids): the road and the object around the click,
// then the geometric fit with the clicked class's size.
#include "granular_core/cuboids/click_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

#include "levelled_object.h"

namespace granular {
namespace {

double horizontalDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return (a.head<2>() - b.head<2>()).norm();
}

// The road's z under the click (ClickConfig::ground_radius, ground_percentile).
double groundUnder(const std::vector<Eigen::Vector3d>& cloud, const Eigen::Vector3d& click,
                   const ClickConfig& config) {
  std::vector<double> heights;
  for (const Eigen::Vector3d& point : cloud) {
    if (horizontalDistance(point, click) <= config.ground_radius) {
      heights.push_back(point.z());
    }
  }
  if (heights.empty()) {
    return click.z();
  }
  const auto rank = static_cast<std::size_t>(
      std::floor(config.ground_percentile / 100.0 * static_cast<double>(heights.size() - 1)));
  std::nth_element(heights.begin(), heights.begin() + rank, heights.end());
  return heights[rank];
}

}  // namespace

ClickedCuboid fitCuboidAtClick(const std::vector<Eigen::Vector3d>& cloud,
                               const Eigen::Vector3d& click, const std::string& label,
                               const SizePrior& size, const CuboidConfig& config) {
  validate(config);
  const ClickConfig& settings = config.click;
  char where[160];
  std::snprintf(where, sizeof(where), "the click (%g, %g, %g)", click.x(), click.y(), click.z());
  if (!click.allFinite()) {
    throw std::invalid_argument(std::string(where) + " is not finite: no box");
  }
  // Without a point within ground_radius the road's height would be the click's own, and a
  // box there (a click on rviz's grid far from the cloud) nonsense.
  double nearest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& point : cloud) {
    if (point.allFinite()) {
      nearest = std::min(nearest, horizontalDistance(point, click));
    }
  }
  if (!std::isfinite(nearest)) {
    throw std::invalid_argument("the cloud has no finite point: nothing to fit a box to");
  }
  if (nearest > settings.ground_radius) {
    char text[300];
    std::snprintf(text, sizeof(text),
                  "%s is %.1f m from the nearest point of the cloud, farther than "
                  "click.ground_radius (%.1f m): click on the cloud",
                  where, nearest, settings.ground_radius);
    throw std::invalid_argument(text);
  }
  const double ground = groundUnder(cloud, click, settings);
  GroundPlane road;
  road.offset = -ground;

  const double reach = std::max(settings.reach, std::hypot(size.length, size.width));
  std::vector<Eigen::Vector3d> candidates;
  for (const Eigen::Vector3d& point : cloud) {
    const double height = road.heightOf(point);
    if (point.allFinite() && horizontalDistance(point, click) <= reach &&
        height >= config.points.min_height && height <= config.points.max_height) {
      candidates.push_back(point);
    }
  }
  const std::vector<std::size_t> cluster = cuboids::birdsEyeClusters(candidates, settings.gap);
  std::set<std::size_t> clicked_clusters;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (horizontalDistance(candidates[i], click) <= settings.seed_radius) {
      clicked_clusters.insert(cluster[i]);
    }
  }
  ObjectView object;
  object.ground = road;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (clicked_clusters.count(cluster[i])) {
      object.points.push_back(candidates[i]);
    }
  }

  if (object.points.size() >= settings.min_points) {
    CuboidConfig with_class = config;
    with_class.priors = {{label, size}};
    with_class.geometric.classes = {label};
    if (std::optional<FittedCuboid> fitted = GeometricCuboidFitter(with_class).fit(object)) {
      fitted->label = label;
      return {*fitted, ground};
    }
  }
  const OrientedBox standing(Eigen::Vector3d(click.x(), click.y(), ground + size.height / 2),
                             Eigen::Quaterniond::Identity(),
                             Eigen::Vector3d(size.length, size.width, size.height));
  return {FittedCuboid{label, 1.0, standing, 0}, ground};
}

}  // namespace granular
