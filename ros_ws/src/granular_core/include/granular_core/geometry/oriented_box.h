#pragma once

#include <Eigen/Geometry>

namespace granular {

/// A box with full 3-D orientation, as a detector reports it: centre and orientation in the
/// sensor frame, size = (length along the box x axis, width along y, height along z), metres.
///
/// The object frame of a box has its origin at the centre of the box's bottom face and the box's
/// axes (x forward along the length, y left, z up), so a vehicle body lies in 0 <= z <= height.
class OrientedBox {
 public:
  /// Validates and stores a box. A non-unit quaternion is normalised. Throws std::invalid_argument
  /// (with the offending values in the message) when the centre is not finite, a size component
  /// is not finite and positive, or the quaternion is not finite or (almost) zero.
  OrientedBox(const Eigen::Vector3d& centre, const Eigen::Quaterniond& orientation,
              const Eigen::Vector3d& size);

  const Eigen::Vector3d& centre() const { return centre_; }
  /// Unit quaternion, sensor frame <- box axes.
  const Eigen::Quaterniond& orientation() const { return orientation_; }
  const Eigen::Vector3d& size() const { return size_; }

  /// Maps sensor-frame points into the object frame: translate(0, 0, height/2) * pose^-1.
  Eigen::Isometry3d sensorToObject() const;

  /// Heading of the box's x axis projected on the sensor's x-y plane, rad in [-pi, pi].
  double yaw() const;

  /// Distance from the sensor origin to the box centre, metres.
  double range() const { return centre_.norm(); }

 private:
  Eigen::Vector3d centre_;
  Eigen::Quaterniond orientation_;
  Eigen::Vector3d size_;
};

}  // namespace granular
