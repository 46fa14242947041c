#include "granular_core/cuboids/vehicle_split.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "granular_core/geometry/footprint.h"

namespace granular {
namespace {

// The height of `point` above the object's road (a flat road through its lowest point when it
// has none).
double heightAbove(const ObjectView& object, const Eigen::Vector3d& point, double lowest) {
  return object.ground ? object.ground->heightOf(point) : point.z() - lowest;
}

// A cut across a direction: where (a distance along it) and how far its valley lies below
// the lower of the tops on either side.
struct Cut {
  Eigen::Vector2d axis;
  double at = 0.0;
  double drop = 0.0;
};

// Where to cut `points` along `axis` (a unit vector on the ground), or none; none either where
// the points span at most `min_extent` along it.
std::optional<Cut> cutAlong(const ObjectView& object, const std::vector<std::size_t>& points,
                            const Eigen::Vector2d& axis, double lowest,
                            const VehicleSplitConfig& config, double min_extent = 0.0) {
  double from = 1e9, to = -1e9;
  for (const std::size_t i : points) {
    const double along = object.points[i].head<2>().dot(axis);
    from = std::min(from, along), to = std::max(to, along);
  }
  if (to - from <= min_extent) {
    return std::nullopt;
  }
  const auto bins = static_cast<std::size_t>((to - from) / config.bin) + 1;
  std::vector<double> top(bins, 0.0);
  for (const std::size_t i : points) {
    const double height = heightAbove(object, object.points[i], lowest);
    if (height < config.road_height) {
      continue;
    }
    const auto bin = std::min(bins - 1, static_cast<std::size_t>(
                                            (object.points[i].head<2>().dot(axis) - from) /
                                            config.bin));
    top[bin] = std::max(top[bin], height);
  }
  // A run of empty bins shorter than min_gap is the spacing of the scan's returns, not a gap
  // between two bodies: it takes the lower of the tops beside it.
  const auto shortest_gap = static_cast<std::size_t>(std::ceil(config.min_gap / config.bin - 1e-9));
  std::vector<bool> seen(bins, false);
  for (const std::size_t i : points) {
    seen[std::min(bins - 1, static_cast<std::size_t>(
                               (object.points[i].head<2>().dot(axis) - from) / config.bin))] = true;
  }
  for (std::size_t bin = 0; bin < bins;) {
    if (seen[bin]) {
      ++bin;
      continue;
    }
    std::size_t end = bin;
    while (end < bins && !seen[end]) {
      ++end;
    }
    if (bin > 0 && end < bins && end - bin < shortest_gap) {
      std::fill(top.begin() + static_cast<long>(bin), top.begin() + static_cast<long>(end),
                std::min(top[bin - 1], top[end]));
    }
    bin = end;
  }
  const auto edge = static_cast<std::size_t>(config.min_piece / config.bin);
  std::optional<std::size_t> best;
  double best_drop = 0.0;
  for (std::size_t bin = edge; bin + edge < bins; ++bin) {
    const double before = *std::max_element(top.begin(), top.begin() + static_cast<long>(bin));
    const double after = *std::max_element(top.begin() + static_cast<long>(bin) + 1, top.end());
    if (top[bin] <= std::min(before, after) - config.min_drop &&
        (!best || top[bin] < top[*best])) {
      best = bin;
      best_drop = std::min(before, after) - top[bin];
    }
  }
  if (!best) {
    return std::nullopt;
  }
  return Cut{axis, from + (static_cast<double>(*best) + 0.5) * config.bin, best_drop};
}

void split(const ObjectView& object, std::vector<std::size_t> points, double lowest,
           const VehicleSplitConfig& config, int depth, std::vector<ObjectView>& pieces) {
  std::vector<Eigen::Vector2d> footprint;
  double top = 0.0;
  for (const std::size_t i : points) {
    footprint.push_back(object.points[i].head<2>());
    top = std::max(top, heightAbove(object, object.points[i], lowest));
  }
  const Rectangle rectangle = minimumAreaRectangle(footprint);
  const Eigen::Vector2d length_axis(std::cos(rectangle.yaw), std::sin(rectangle.yaw));
  const Eigen::Vector2d width_axis(-length_axis.y(), length_axis.x());
  std::optional<Cut> cut;
  if (depth < config.max_cuts && top <= config.max_top) {
    // Across the wider excess first: cars side by side, then nose to tail.
    if (rectangle.width > config.max_width) {
      cut = cutAlong(object, points, width_axis, lowest, config);
      if (!cut) {
        // Cars side by side seen from their fronts: the row is the longer side.
        cut = cutAlong(object, points, length_axis, lowest, config);
      }
    }
    if (!cut && rectangle.length > config.max_length) {
      cut = cutAlong(object, points, length_axis, lowest, config);
    }
    // The footprint of two cars seen at a slant can make a minimum-area rectangle whose sides
    // follow neither car: then the deepest valley across any direction along which the points
    // span more than a car's width.
    if (!cut && config.search_step_deg > 0.0 &&
        (rectangle.width > config.search_min_width || rectangle.length > config.max_length)) {
      for (double deg = 0.0; deg < 180.0; deg += config.search_step_deg) {
        const double angle = rectangle.yaw + deg * M_PI / 180.0;
        const auto found = cutAlong(object, points, {std::cos(angle), std::sin(angle)}, lowest,
                                    config, config.max_width);
        if (found && (!cut || found->drop > cut->drop)) {
          cut = found;
        }
      }
    }
  }
  if (!cut) {
    ObjectView piece = object;
    piece.points.clear();
    for (const std::size_t i : points) {
      piece.points.push_back(object.points[i]);
    }
    pieces.push_back(std::move(piece));
    return;
  }
  std::vector<std::size_t> near, far;
  for (const std::size_t i : points) {
    (object.points[i].head<2>().dot(cut->axis) < cut->at ? near : far).push_back(i);
  }
  split(object, std::move(near), lowest, config, depth + 1, pieces);
  split(object, std::move(far), lowest, config, depth + 1, pieces);
}

}  // namespace

std::vector<ObjectView> splitVehicles(const ObjectView& object, const VehicleSplitConfig& config) {
  if (!config.enabled || object.points.size() < 3) {
    return {object};
  }
  double lowest = 1e9;
  for (const Eigen::Vector3d& p : object.points) {
    lowest = std::min(lowest, p.z());
  }
  std::vector<std::size_t> points(object.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = i;
  }
  std::vector<ObjectView> pieces;
  split(object, std::move(points), lowest, config, 0, pieces);
  return pieces;
}

}  // namespace granular
