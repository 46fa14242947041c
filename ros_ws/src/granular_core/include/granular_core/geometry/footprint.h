#pragma once

#include <vector>

#include <Eigen/Core>

namespace granular {

/// The convex hull of points in the plane, counter-clockwise from the lowest-leftmost point
/// (Andrew's monotone chain); collinear points on the hull's edges are left out. Fewer than
/// three distinct points give those points.
std::vector<Eigen::Vector2d> convexHull(std::vector<Eigen::Vector2d> points);

/// A rectangle in the plane: centre, the direction of its length (yaw, rad) and its two sides.
struct Rectangle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0.0;     ///< of the length axis, in (-pi/2, pi/2]
  double length = 0.0;  ///< the longer side
  double width = 0.0;   ///< the shorter side
};

/// The rectangle of least area enclosing the points: one side lies along an edge of their
/// convex hull (rotating calipers). Its centre is the middle of the extremes (not the
/// centroid), its length the longer side. Empty input gives a zero rectangle at the origin.
Rectangle minimumAreaRectangle(const std::vector<Eigen::Vector2d>& points);

}  // namespace granular
