// Synthetic scans of upright boxes: the side faces a sensor sees, sampled on a regular grid,
// standing on a road plane, for the cuboid tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Geometry>

namespace granular {
namespace testing_support {

// A box standing on a road: centre of its footprint (x, y in the road's frame), heading of its
// length axis about the road's normal, and its size.
struct StandingBox {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  Eigen::Vector3d size = Eigen::Vector3d(4.5, 1.8, 1.5);
};

// Points of the box's side faces (not its roof) that face `sensor`, every `step` metres along
// a face and up from `bottom` to the roof, in the road's frame (road at z = 0). `visible`, when
// given, keeps only the points it accepts (u, v, h: along the length, the width, up, from the
// centre of the footprint), e.g. to hide part of a face.
template <typename Keep>
std::vector<Eigen::Vector3d> seenFaces(const StandingBox& box, const Eigen::Vector3d& sensor,
                                       double step, Keep visible, double bottom = 0.35) {
  const Eigen::Rotation2Dd turn(box.yaw);
  const double l = box.size.x() / 2, w = box.size.y() / 2;
  // Each face: its outward normal (box axes) and its two ends.
  const struct {
    Eigen::Vector2d normal, from, to;
  } faces[4] = {{{1, 0}, {l, -w}, {l, w}},
                {{-1, 0}, {-l, -w}, {-l, w}},
                {{0, 1}, {-l, w}, {l, w}},
                {{0, -1}, {-l, -w}, {l, -w}}};
  std::vector<Eigen::Vector3d> points;
  for (const auto& face : faces) {
    const Eigen::Vector2d middle = box.centre + turn * ((face.from + face.to) / 2);
    if ((sensor.head<2>() - middle).dot(turn * face.normal) <= 0.0) {
      continue;
    }
    const double length = (face.to - face.from).norm();
    const int steps = static_cast<int>(std::round(length / step));
    for (int i = 0; i <= steps; ++i) {
      const Eigen::Vector2d local = face.from + (face.to - face.from) * (double(i) / steps);
      for (double h = bottom; h <= box.size.z() + 1e-9; h += step) {
        if (!visible(local.x(), local.y(), h)) {
          continue;
        }
        const Eigen::Vector2d p = box.centre + turn * local;
        points.emplace_back(p.x(), p.y(), h);
      }
    }
  }
  return points;
}

inline std::vector<Eigen::Vector3d> seenFaces(const StandingBox& box,
                                              const Eigen::Vector3d& sensor, double step) {
  return seenFaces(box, sensor, step, [](double, double, double) { return true; });
}

// The box's faces that face `sensor` (seenFaces) and its roof, every `step` metres, where
// `visible` (u, v, h as seenFaces') keeps them: what a sensor on a mast sees of a car.
template <typename Keep>
std::vector<Eigen::Vector3d> seenFacesAndRoof(const StandingBox& box, const Eigen::Vector3d& sensor,
                                              double step, Keep visible) {
  std::vector<Eigen::Vector3d> points = seenFaces(box, sensor, step, visible);
  const Eigen::Rotation2Dd turn(box.yaw);
  const double l = box.size.x() / 2, w = box.size.y() / 2;
  for (double u = -l; u <= l + 1e-9; u += step) {
    for (double v = -w; v <= w + 1e-9; v += step) {
      if (visible(u, v, box.size.z())) {
        const Eigen::Vector2d p = box.centre + turn * Eigen::Vector2d(u, v);
        points.emplace_back(p.x(), p.y(), box.size.z());
      }
    }
  }
  return points;
}

// `points` less those hidden from a sensor at the origin behind `nearer`: within the bearings
// `nearer` spans (none may straddle +-180 degrees) and farther than its nearest point.
inline std::vector<Eigen::Vector3d> unhiddenBy(const std::vector<Eigen::Vector3d>& points,
                                               const std::vector<Eigen::Vector3d>& nearer) {
  double low = M_PI, high = -M_PI, nearest = 1e9;
  for (const Eigen::Vector3d& p : nearer) {
    const double bearing = std::atan2(p.y(), p.x());
    low = std::min(low, bearing), high = std::max(high, bearing);
    nearest = std::min(nearest, p.head<2>().norm());
  }
  std::vector<Eigen::Vector3d> kept;
  for (const Eigen::Vector3d& p : points) {
    const double bearing = std::atan2(p.y(), p.x());
    if (bearing < low || bearing > high || p.head<2>().norm() <= nearest) {
      kept.push_back(p);
    }
  }
  return kept;
}

// `points` moved by `motion`.
inline std::vector<Eigen::Vector3d> moved(const std::vector<Eigen::Vector3d>& points,
                                          const Eigen::Isometry3d& motion) {
  std::vector<Eigen::Vector3d> result;
  for (const Eigen::Vector3d& point : points) {
    result.push_back(motion * point);
  }
  return result;
}

}  // namespace testing_support
}  // namespace granular
