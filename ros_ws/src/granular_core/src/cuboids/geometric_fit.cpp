#include <algorithm>
#include <cmath>
#include <limits>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "levelled_object.h"

namespace granular {
namespace {

// The prior of `classes` whose height is nearest `height`; the first on a tie.
const SizePrior* nearestPrior(const CuboidConfig& config, double height) {
  const SizePrior* best = nullptr;
  double best_gap = std::numeric_limits<double>::infinity();
  for (const std::string& name : config.geometric.classes) {
    const SizePrior& prior = config.priors.at(name);
    const double gap = std::abs(prior.height - height);
    if (gap < best_gap) {
      best_gap = gap;
      best = &prior;
    }
  }
  return best;
}

// 0 when the rectangle's u axis is the object's length, 1 for v (GeometricCuboidFitter).
int lengthAxis(const Eigen::Vector2d& extent, const SizePrior* prior,
               const GeometricFitConfig& config) {
  const int longer = extent.x() >= extent.y() ? 0 : 1;
  if (prior == nullptr || extent[longer] > prior->width + config.width_tolerance ||
      extent[1 - longer] >= config.face_depth) {
    return longer;
  }
  return 1 - longer;
}

}  // namespace

GeometricCuboidFitter::GeometricCuboidFitter(const CuboidConfig& config) : config_(config) {
  validate(config_);
}

std::optional<FittedCuboid> GeometricCuboidFitter::fit(const ObjectView& object) const {
  const std::optional<cuboids::LevelledObject> levelled =
      cuboids::levelObject(object, config_.points);
  if (!levelled) {
    return std::nullopt;
  }
  AxisRectangle rectangle = cuboids::lshapeRectangle(*levelled, config_.lshape);
  const Eigen::Vector2d seen = rectangle.extent();
  const SizePrior* prior = seen.maxCoeff() >= config_.geometric.min_extent
                               ? nearestPrior(config_, levelled->top)
                               : nullptr;
  const int length_axis = lengthAxis(seen, prior, config_.geometric);
  if (prior != nullptr) {
    rectangle = cuboids::grownFromSeenCorner(rectangle, levelled->sensor, length_axis,
                                             prior->length, prior->width);
  }
  const double height = prior != nullptr && levelled->points.size() < config_.geometric.height_points
                            ? prior->height
                            : levelled->top;
  // A rectangle of points in one cell has no extent: it gets one cell's.
  const Eigen::Vector2d extent = rectangle.extent().cwiseMax(config_.lshape.cell);
  const double yaw = rectangle.heading + (length_axis == 1 ? M_PI / 2 : 0.0);
  FittedCuboid cuboid{
      kUnknownLabel, 1.0,
      cuboids::sensorBox(levelled->levelling, rectangle.centre(), yaw,
                         Eigen::Vector3d(extent[length_axis], extent[1 - length_axis],
                                         std::max(height, config_.lshape.cell))),
      levelled->points.size()};
  return cuboid;
}

}  // namespace granular
