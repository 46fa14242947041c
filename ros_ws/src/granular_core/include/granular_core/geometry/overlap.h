#pragma once

#include <vector>

#include <Eigen/Core>

#include "granular_core/geometry/oriented_box.h"

namespace granular {

/// The corners of a box's footprint on the sensor's x-y plane, counter-clockwise: a rectangle
/// about the centre's x and y, turned by yaw(), length by width.
std::vector<Eigen::Vector2d> footprintCorners(const OrientedBox& box);

/// The area where two convex polygons overlap, each given by its corners counter-clockwise
/// (Sutherland-Hodgman clipping). Fewer than three corners is no area.
double convexOverlapArea(const std::vector<Eigen::Vector2d>& a,
                         const std::vector<Eigen::Vector2d>& b);

/// How much two boxes overlap seen from above: the area their footprints share over the
/// smaller footprint's area, in [0, 1]. 1 when one footprint lies inside the other, so a
/// partial box (a rear seen alone) overlaps the whole vehicle's fully.
double birdEyeOverlap(const OrientedBox& a, const OrientedBox& b);

}  // namespace granular
