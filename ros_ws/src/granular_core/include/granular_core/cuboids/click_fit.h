#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "granular_core/cuboids/cuboid_fitter.h"

namespace granular {

/// The box made where a user clicked.
struct ClickedCuboid {
  /// Labelled with the clicked class, score 1; `points` is 0 for a box of the class's size.
  FittedCuboid cuboid;
  double ground = 0.0;  ///< m, the road's z under the click (sensor frame)
};

/// A new box for an object of class `label`, about `size`, where a user clicked at `click` on
/// the frame's `cloud` (both in the sensor frame, the sensor at the origin); config.click says
/// how (ClickConfig):
/// 1. The road: a level plane at the click.ground_percentile of the heights of the points
///    within click.ground_radius (x-y) of the click (the click's own height without any).
/// 2. The object: the points between config.points.min_height and max_height above it and
///    within click.reach (x-y) of the click, clustered from above (birds-eye cells of
///    click.gap), of the clusters with a point within click.seed_radius of the click.
/// 3. The box: GeometricCuboidFitter with `size` as the only prior, so that a face seen alone
///    grows away from the sensor to the class's length or width.
/// With fewer than click.min_points object points, the box has `size`, stands on the road,
/// is centred on the click and heads along x. Validates `config`; throws std::invalid_argument
/// for a click that is not finite, a cloud without a finite point, or a click farther than
/// click.ground_radius (x-y) from every point (each message names the click).
ClickedCuboid fitCuboidAtClick(const std::vector<Eigen::Vector3d>& cloud,
                               const Eigen::Vector3d& click, const std::string& label,
                               const SizePrior& size, const CuboidConfig& config);

}  // namespace granular
