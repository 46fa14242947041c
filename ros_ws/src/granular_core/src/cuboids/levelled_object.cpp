#include "levelled_object.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace granular {
namespace cuboids {

namespace {

// Leaves out the points above the lowest gap in height that ObjectPointsConfig calls an
// overhang, and lowers the top to the body's.
void dropOverhang(LevelledObject& object, const ObjectPointsConfig& band) {
  std::vector<double> heights;
  heights.reserve(object.points.size());
  for (const Eigen::Vector3d& point : object.points) {
    heights.push_back(point.z());
  }
  std::sort(heights.begin(), heights.end());
  const double gap = spanAt(object.range, band.overhang_gap, band.overhang_gap_deg);
  const double most_above = band.overhang_share * static_cast<double>(heights.size());
  for (std::size_t i = 1; i < heights.size(); ++i) {
    if (static_cast<double>(heights.size() - i) > most_above) {
      continue;
    }
    if (heights[i] - heights[i - 1] > gap) {
      const double body_top = heights[i - 1];
      object.points.erase(std::remove_if(object.points.begin(), object.points.end(),
                                         [&](const Eigen::Vector3d& p) { return p.z() > body_top; }),
                          object.points.end());
      object.top = body_top;
      return;
    }
  }
}

}  // namespace

double spanAt(double range, double metres, double degrees) {
  return std::max(metres, range * std::tan(degrees * M_PI / 180.0));
}

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
  levelled.range = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& point : levelled.points) {
    levelled.range = std::min(levelled.range, (point.head<2>() - levelled.sensor).norm());
  }
  dropOverhang(levelled, band);
  return levelled;
}

std::vector<Eigen::Vector2d> outline(const std::vector<Eigen::Vector2d>& points,
                                     const Eigen::Vector2d& sensor, double step_deg) {
  if (points.empty()) {
    return {};
  }
  // Each point's bearing bin and squared range; then per bin, from the least to the greatest,
  // its nearest point (the first on a tie). The bins span at most a turn, so a table over
  // them replaces sorting the points.
  const double step = step_deg * M_PI / 180.0;
  std::vector<std::int64_t> bin_of(points.size());
  std::vector<double> range_sq(points.size());
  std::int64_t least = std::numeric_limits<std::int64_t>::max();
  std::int64_t greatest = std::numeric_limits<std::int64_t>::min();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d ray = points[i] - sensor;
    bin_of[i] = static_cast<std::int64_t>(std::floor(std::atan2(ray.y(), ray.x()) / step));
    range_sq[i] = ray.squaredNorm();
    least = std::min(least, bin_of[i]);
    greatest = std::max(greatest, bin_of[i]);
  }
  constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> nearest_in(static_cast<std::size_t>(greatest - least + 1), kNone);
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::size_t& best = nearest_in[static_cast<std::size_t>(bin_of[i] - least)];
    if (best == kNone || range_sq[i] < range_sq[best]) {
      best = i;
    }
  }
  std::vector<Eigen::Vector2d> nearest;
  for (const std::size_t index : nearest_in) {
    if (index != kNone) {
      nearest.push_back(points[index]);
    }
  }
  return nearest;
}

Eigen::Vector2d extentAbove(const LevelledObject& object, const AxisRectangle& rectangle,
                            double height) {
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high = -low;
  const RectangleAxes axes(rectangle);
  for (const Eigen::Vector3d& point : object.points) {
    if (point.z() >= height) {
      const Eigen::Vector2d c = axes.coordinates(point.head<2>());
      low = low.cwiseMin(c);
      high = high.cwiseMax(c);
    }
  }
  return (high.array() >= low.array()).all() ? Eigen::Vector2d(high - low) : rectangle.extent();
}

Eigen::Vector2d bodyExtent(const LevelledObject& object, const AxisRectangle& rectangle) {
  return extentAbove(object, rectangle, object.top / 3);
}

double acrossShortfall(const LevelledObject& object) {
  // Bearings from the object's mean direction, so that none wraps around at +-180 degrees.
  Eigen::Vector2d middle = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& point : object.points) {
    middle += point.head<2>() - object.sensor;
  }
  std::vector<double> bearings;
  bearings.reserve(object.points.size());
  for (const Eigen::Vector3d& point : object.points) {
    const Eigen::Vector2d from_sensor = point.head<2>() - object.sensor;
    bearings.push_back(std::atan2(middle.x() * from_sensor.y() - middle.y() * from_sensor.x(),
                                  middle.dot(from_sensor)));
  }
  std::sort(bearings.begin(), bearings.end());
  // Returns of one column (one bearing, several rings) differ by rounding only.
  constexpr double kSameBearing = 1.0e-4;  // rad
  std::vector<double> steps;
  for (std::size_t i = 1; i < bearings.size(); ++i) {
    if (bearings[i] - bearings[i - 1] > kSameBearing) {
      steps.push_back(bearings[i] - bearings[i - 1]);
    }
  }
  if (steps.empty()) {
    return 0.0;
  }
  std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
  return 2.0 * object.range * std::tan(steps[steps.size() / 2]);
}

int lengthAxis(const Eigen::Vector2d& seen, double width, double tolerance,
               const Eigen::Vector2d& sight, const std::function<double()>& across_shortfall) {
  const int longer = seen.x() >= seen.y() ? 0 : 1;
  if (seen[longer] > width + tolerance) {
    return longer;
  }
  const int across = std::abs(sight.x()) >= std::abs(sight.y()) ? 1 : 0;
  // How far each extent is from the class's width; across the line of sight, a face that
  // looks narrower may be as wide as the class.
  const auto gapToWidth = [&](int axis) {
    double gap = std::abs(seen[axis] - width);
    if (axis == across && seen[axis] < width - tolerance && across_shortfall) {
      gap = std::max(0.0, gap - across_shortfall());
    }
    return gap;
  };
  const double longer_gap = gapToWidth(longer);
  const double shorter_gap = gapToWidth(1 - longer);
  // Both as wide as the class: the object is seen end on, the roof or bonnet making it look
  // deep along the line of sight, which is then the length.
  if (longer_gap <= tolerance && shorter_gap <= tolerance) {
    return 1 - across;
  }
  return longer_gap <= shorter_gap ? 1 - longer : longer;
}

AxisRectangle enclosingRectangle(const LevelledObject& object, double heading) {
  AxisRectangle rectangle;
  rectangle.heading = heading;
  rectangle.min = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  rectangle.max = -rectangle.min;
  const RectangleAxes axes(rectangle);
  for (const Eigen::Vector3d& point : object.points) {
    const Eigen::Vector2d c = axes.coordinates(point.head<2>());
    rectangle.min = rectangle.min.cwiseMin(c);
    rectangle.max = rectangle.max.cwiseMax(c);
  }
  return rectangle;
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
  const RectangleAxes axes(rectangle);
  for (const Eigen::Vector2d& point : xy) {
    const Eigen::Vector2d c = axes.coordinates(point);
    rectangle.min = rectangle.min.cwiseMin(c);
    rectangle.max = rectangle.max.cwiseMax(c);
  }
  return rectangle;
}

AxisRectangle grownFromSeenCorner(AxisRectangle rectangle, const Eigen::Vector2d& sensor,
                                  int length_axis, double length, double width,
                                  const SeenEmpty& seen_empty, double step, double inset) {
  const Eigen::Vector2d seen_from = rectangle.coordinates(sensor);
  for (int axis = 0; axis < 2; ++axis) {
    const double wanted = axis == length_axis ? length : width;
    const double low = rectangle.min[axis], high = rectangle.max[axis];
    if (high - low >= wanted) {
      continue;
    }
    // The end nearer the sensor stays (for a face seen edge on, low == high: the sensor's side).
    const bool grows_up = seen_from[axis] <= (low + high) / 2;
    const double seen_end = grows_up ? high : low;
    const double direction = grows_up ? 1.0 : -1.0;
    double growth = wanted - (high - low);
    // Only a face seen over half its class's extent is tested: behind a face seen head on
    // (a rear), a degree of yaw error takes the probes off the object into seen space.
    if (seen_empty && high - low >= wanted / 2) {
      // Just behind the face turned to the sensor, continued: the sensor would have hit it.
      const int across = 1 - axis;
      const bool near_min =
          seen_from[across] <= (rectangle.min[across] + rectangle.max[across]) / 2;
      Eigen::Vector2d probe;
      probe[across] = near_min ? rectangle.min[across] + inset : rectangle.max[across] - inset;
      for (double beyond = step; beyond <= growth; beyond += step) {
        probe[axis] = seen_end + direction * beyond;
        if (seen_empty(rectangle.point(probe))) {
          growth = beyond - step;
          break;
        }
      }
    }
    (grows_up ? rectangle.max : rectangle.min)[axis] = seen_end + direction * growth;
  }
  return rectangle;
}

std::size_t refutedGrowth(const AxisRectangle& rectangle, const Eigen::Vector2d& sensor,
                          int length_axis, double length, double width,
                          const std::function<bool(const Eigen::Vector2d&)>& refutes,
                          double step, std::size_t enough) {
  const AxisRectangle grown =
      grownFromSeenCorner(rectangle, sensor, length_axis, length, width, nullptr);
  std::size_t refuted = 0;
  for (double u = grown.min.x() + step / 2; u < grown.max.x() && refuted < enough; u += step) {
    for (double v = grown.min.y() + step / 2; v < grown.max.y() && refuted < enough; v += step) {
      const bool beyond = u < rectangle.min.x() - step || u > rectangle.max.x() + step ||
                          v < rectangle.min.y() - step || v > rectangle.max.y() + step;
      if (beyond && refutes(rectangle.point(Eigen::Vector2d(u, v)))) {
        ++refuted;
      }
    }
  }
  return refuted;
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
