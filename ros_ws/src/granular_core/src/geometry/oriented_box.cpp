#include "granular_core/geometry/oriented_box.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace granular {
namespace {

// Below this norm a quaternion carries no usable rotation: normalising it would amplify
// rounding noise into an arbitrary orientation.
constexpr double kMinQuaternionNorm = 1e-6;

std::string format(const Eigen::Vector3d& v) {
  std::ostringstream out;
  out << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return out.str();
}

}  // namespace

OrientedBox::OrientedBox(const Eigen::Vector3d& centre, const Eigen::Quaterniond& orientation,
                         const Eigen::Vector3d& size)
    : centre_(centre), orientation_(orientation), size_(size) {
  if (!centre.allFinite()) {
    throw std::invalid_argument("box centre is not finite: " + format(centre));
  }
  if (!size.allFinite() || (size.array() <= 0.0).any()) {
    throw std::invalid_argument("box size must be finite and positive, got " + format(size));
  }
  const double norm = orientation.norm();
  if (!std::isfinite(norm) || norm < kMinQuaternionNorm) {
    std::ostringstream message;
    message << "box orientation is not a usable quaternion: (x, y, z, w) = (" << orientation.x()
            << ", " << orientation.y() << ", " << orientation.z() << ", " << orientation.w()
            << ')';
    throw std::invalid_argument(message.str());
  }
  orientation_.normalize();
}

Eigen::Isometry3d OrientedBox::sensorToObject() const {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = orientation_.toRotationMatrix();
  pose.translation() = centre_;
  return Eigen::Translation3d(0.0, 0.0, size_.z() / 2.0) * pose.inverse();
}

double OrientedBox::yaw() const {
  const Eigen::Vector3d forward = orientation_ * Eigen::Vector3d::UnitX();
  return std::atan2(forward.y(), forward.x());
}

}  // namespace granular
