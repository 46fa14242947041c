#pragma once

#include <vector>

#include <Eigen/Core>

#include "granular_core/cuboids/cuboid_config.h"

namespace granular {

/// A rectangle in the plane given by a direction and the extents of points along it: axis u at
/// `heading` (rad), axis v at heading + 90 deg, and the points' least and greatest coordinates
/// along each (`min`, `max`: (u, v) in metres).
struct AxisRectangle {
  double heading = 0.0;
  Eigen::Vector2d min = Eigen::Vector2d::Zero();
  Eigen::Vector2d max = Eigen::Vector2d::Zero();

  Eigen::Vector2d u() const;
  Eigen::Vector2d v() const;
  /// Extents along u and v.
  Eigen::Vector2d extent() const { return max - min; }
  /// The middle of the rectangle in the plane.
  Eigen::Vector2d centre() const;
  /// Coordinates (u, v) of a point of the plane.
  Eigen::Vector2d coordinates(const Eigen::Vector2d& point) const;
  /// The point of the plane at coordinates (u, v).
  Eigen::Vector2d point(const Eigen::Vector2d& coordinates) const;
};

/// AxisRectangle::coordinates for many points: the heading's cosine and sine taken once, not
/// four times a point.
class RectangleAxes {
 public:
  explicit RectangleAxes(const AxisRectangle& rectangle) : u_(rectangle.u()), v_(rectangle.v()) {}
  Eigen::Vector2d coordinates(const Eigen::Vector2d& point) const {
    return {point.dot(u_), point.dot(v_)};
  }

 private:
  Eigen::Vector2d u_, v_;
};

/// The points merged to one per `cell` (m) square, at the mean of the cell's points, in the
/// order of their cells. Empty input gives empty output.
std::vector<Eigen::Vector2d> thinnedPoints(const std::vector<Eigen::Vector2d>& points,
                                           double cell);

/// The criterion's score of the rectangle direction `theta` (rad) for `points`; larger is
/// better. `points` should be centred near the origin (the scores sum squared coordinates).
double lshapeScore(const std::vector<Eigen::Vector2d>& points, double theta,
                   const LShapeConfig& config);

/// The L-shape fit (Zhang et al. 2017): the direction in [0, 90) deg that scores best, searched
/// as LShapeConfig says, and the points' rectangle along it (heading in [0, pi/2)). Equal
/// scores go to the smaller angle. Needs at least one point; the points are used as given
/// (thin them first with thinnedPoints).
AxisRectangle fitLShape(const std::vector<Eigen::Vector2d>& points, const LShapeConfig& config);

}  // namespace granular
