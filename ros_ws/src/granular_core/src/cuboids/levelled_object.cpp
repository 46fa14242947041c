#include "levelled_object.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

namespace granular {
namespace cuboids {

std::optional<LevelledObject> levelObject(const ObjectView& object,
                                          const ObjectPointsConfig& band) {
  LevelledObject levelled;
  double min_height = band.min_height;
  if (object.ground) {
    levelled.levelling = object.ground->levelling();
  } else {
    double lowest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& point : object.points) {
      if (point.allFinite()) {
        lowest = std::min(lowest, point.z());
      }
    }
    if (!std::isfinite(lowest)) {
      return std::nullopt;
    }
    levelled.levelling = Eigen::Translation3d(0.0, 0.0, -lowest);
    min_height = 0.0;  // the lowest point is the road: everything above it is the object
  }
  levelled.points.reserve(object.points.size());
  levelled.top = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& point : object.points) {
    const Eigen::Vector3d q = levelled.levelling * point;
    if (q.allFinite() && q.z() >= min_height && q.z() <= band.max_height) {
      levelled.points.push_back(q);
      levelled.top = std::max(levelled.top, q.z());
    }
  }
  if (levelled.points.size() < band.min_points) {
    return std::nullopt;
  }
  levelled.sensor = (levelled.levelling * object.sensor).head<2>();
  return levelled;
}

std::vector<Eigen::Vector2d> outline(const std::vector<Eigen::Vector2d>& points,
                                     const Eigen::Vector2d& sensor, double step_deg) {
  // (bearing bin, squared range, index), sorted: each bin's first is its nearest point.
  std::vector<std::tuple<std::int64_t, double, std::size_t>> bins;
  bins.reserve(points.size());
  const double step = step_deg * M_PI / 180.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d ray = points[i] - sensor;
    bins.emplace_back(static_cast<std::int64_t>(std::floor(std::atan2(ray.y(), ray.x()) / step)),
                      ray.squaredNorm(), i);
  }
  std::sort(bins.begin(), bins.end());
  std::vector<Eigen::Vector2d> nearest;
  for (std::size_t k = 0; k < bins.size(); ++k) {
    if (k == 0 || std::get<0>(bins[k]) != std::get<0>(bins[k - 1])) {
      nearest.push_back(points[std::get<2>(bins[k])]);
    }
  }
  return nearest;
}

Eigen::Vector2d bodyExtent(const LevelledObject& object, const AxisRectangle& rectangle) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high = -low;
  for (const Eigen::Vector3d& point : object.points) {
    if (point.z() >= object.top / 3) {
      const Eigen::Vector2d c = rectangle.coordinates(point.head<2>());
      low = low.cwiseMin(c);
      high = high.cwiseMax(c);
    }
  }
  return (high.array() >= low.array()).all() ? Eigen::Vector2d(high - low) : rectangle.extent();
}

int lengthAxis(const Eigen::Vector2d& seen, double width, double tolerance) {
  const int longer = seen.x() >= seen.y() ? 0 : 1;
  const double longer_gap = std::abs(seen[longer] - width);
  const double shorter_gap = std::abs(seen[1 - longer] - width);
  // Both as wide as the class: a corner of a short object, the longer is the length.
  if (seen[longer] > width + tolerance || (longer_gap <= tolerance && shorter_gap <= tolerance)) {
    return longer;
  }
  return longer_gap <= shorter_gap ? 1 - longer : longer;
}

AxisRectangle lshapeRectangle(const LevelledObject& object, const LShapeConfig& config) {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(object.points.size());
  for (const Eigen::Vector3d& point : object.points) {
    xy.push_back(point.head<2>());
  }
  AxisRectangle rectangle =
      fitLShape(config.contour_step_deg > 0.0 ? outline(xy, object.sensor, config.contour_step_deg)
                                              : thinnedPoints(xy, config.cell),
                config);
  // The extremes of every point, not of the cell means.
  for (const Eigen::Vector2d& point : xy) {
    const Eigen::Vector2d c = rectangle.coordinates(point);
    rectangle.min = rectangle.min.cwiseMin(c);
    rectangle.max = rectangle.max.cwiseMax(c);
  }
  return rectangle;
}

AxisRectangle grownFromSeenCorner(AxisRectangle rectangle, const Eigen::Vector2d& sensor,
                                  int length_axis, double length, double width) {
  const Eigen::Vector2d seen_from = rectangle.coordinates(sensor);
  for (int axis = 0; axis < 2; ++axis) {
    const double wanted = axis == length_axis ? length : width;
    const double low = rectangle.min[axis], high = rectangle.max[axis];
    if (high - low >= wanted) {
      continue;
    }
    if (std::abs(seen_from[axis] - low) <= std::abs(seen_from[axis] - high)) {
      rectangle.max[axis] = low + wanted;
    } else {
      rectangle.min[axis] = high - wanted;
    }
  }
  return rectangle;
}

OrientedBox sensorBox(const Eigen::Isometry3d& levelling, const Eigen::Vector2d& centre,
                      double yaw, const Eigen::Vector3d& size) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(centre.x(), centre.y(), size.z() / 2);
  const Eigen::Isometry3d in_sensor = levelling.inverse() * pose;
  return OrientedBox(in_sensor.translation(), Eigen::Quaterniond(in_sensor.linear()), size);
}

}  // namespace cuboids
}  // namespace granular
