#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "granular_core/point_types.h"
#include "granular_core/models/model_config.h"

namespace granular {

/// Plain concatenation (report 5.2.1): the points of every cloud, cloud after cloud, in order.
/// Object clouds share the object frame, so no transformation is needed.
ModelCloud concatenate(const std::vector<ModelCloud>& clouds);

/// A side of an object, in its own frame: front +x, back -x, left +y, right -y.
enum class Side { kFront, kBack, kLeft, kRight };

/// "front", "back", "left" or "right".
const char* sideName(Side side);

/// The half length and half width of a class: the largest |x| and |y| over all points of its
/// objects (at least 1 mm each).
Eigen::Vector2d halfExtents(const std::vector<ModelCloud>& objects);

/// The side an object shows to the sensor: the points of a scan lie on the faces that face
/// the sensor, so their centroid, with x scaled by 1 / half_extent.x() and y by
/// 1 / half_extent.y(), points towards it; the side is the axis direction of its largest
/// component. An empty object counts as front.
Side sideSeen(const ModelCloud& object, const Eigen::Vector2d& half_extent);

/// The objects chosen for an automatic ICP seed (SeedConfig).
struct SeedSelection {
  /// Indices into the objects, side by side (front, back, left, right), most points first;
  /// ties go to the lower index.
  std::vector<std::size_t> indices;
  /// The side of each of those objects.
  std::vector<Side> sides;
  /// Sides that no object shows.
  std::vector<Side> missing_sides;
};

/// For each side, the config.objects_per_side objects with most points that show that side.
SeedSelection selectSeedObjects(const std::vector<ModelCloud>& objects, const SeedConfig& config);

}  // namespace granular
