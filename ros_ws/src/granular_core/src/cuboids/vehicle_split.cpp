#include "granular_core/cuboids/vehicle_split.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "granular_core/cuboids/free_space.h"
#include "granular_core/geometry/footprint.h"
#include "levelled_object.h"

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
  bool gap = false;  // the valley is empty ground between two bodies, not a dip between roofs
};

// Where to cut `points` along `axis` (a unit vector on the ground), or none; none either where
// the points span at most `min_extent` along it. `heights`: each of the object's points' height
// above its road.
std::optional<Cut> cutAlong(const ObjectView& object, const std::vector<std::size_t>& points,
                            const std::vector<double>& heights, const Eigen::Vector2d& axis,
                            const VehicleSplitConfig& config, double min_extent = 0.0,
                            double min_gap = 0.0) {
  std::vector<double> along(points.size());
  double from = 1e9, to = -1e9;
  for (std::size_t k = 0; k < points.size(); ++k) {
    along[k] = object.points[points[k]].head<2>().dot(axis);
    from = std::min(from, along[k]), to = std::max(to, along[k]);
  }
  if (to - from <= min_extent) {
    return std::nullopt;
  }
  const auto bins = static_cast<std::size_t>((to - from) / config.bin) + 1;
  std::vector<double> top(bins, 0.0);
  std::vector<bool> seen(bins, false);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const auto bin = std::min(bins - 1, static_cast<std::size_t>((along[k] - from) / config.bin));
    seen[bin] = true;
    const double height = heights[points[k]];
    if (height >= config.road_height) {
      top[bin] = std::max(top[bin], height);
    }
  }
  // A run of empty bins shorter than min_gap (the config's, or the caller's when longer) is the
  // spacing of the scan's returns, not a gap between two bodies: it takes the lower of the tops
  // beside it.
  const auto shortest_gap = static_cast<std::size_t>(
      std::ceil(std::max(config.min_gap, min_gap) / config.bin - 1e-9));
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
  // The highest top before and after each bin.
  std::vector<double> before(bins, 0.0), after(bins, 0.0);
  for (std::size_t bin = 1; bin < bins; ++bin) {
    before[bin] = std::max(before[bin - 1], top[bin - 1]);
    after[bins - 1 - bin] = std::max(after[bins - bin], top[bins - bin]);
  }
  const auto edge = static_cast<std::size_t>(config.min_piece / config.bin);
  std::optional<std::size_t> best;
  double best_drop = 0.0;
  for (std::size_t bin = std::max<std::size_t>(edge, 1); bin + edge < bins; ++bin) {
    const double lower = std::min(before[bin], after[bin]);
    if (top[bin] <= lower - config.min_drop && (!best || top[bin] < top[*best])) {
      best = bin;
      best_drop = lower - top[bin];
    }
  }
  if (!best) {
    return std::nullopt;
  }
  return Cut{axis, from + (static_cast<double>(*best) + 0.5) * config.bin, best_drop,
             !seen[*best]};
}

// The rectangle of `points` along the sides of their L-shape (the outline's two edges), as a
// Rectangle: its length the longer side.
Rectangle lshapeFootprint(const ObjectView& object, const std::vector<std::size_t>& points,
                          const LShapeConfig& lshape) {
  cuboids::LevelledObject footprint;
  footprint.sensor = object.sensor.head<2>();
  for (const std::size_t i : points) {
    footprint.points.push_back(object.points[i]);
  }
  const AxisRectangle fitted = cuboids::lshapeRectangle(footprint, lshape);
  const Eigen::Vector2d extent = fitted.extent();
  const int longer = extent.x() >= extent.y() ? 0 : 1;
  Rectangle rectangle;
  rectangle.centre = fitted.centre();
  rectangle.yaw = fitted.heading + (longer == 1 ? M_PI / 2 : 0.0);
  rectangle.length = extent[longer];
  rectangle.width = extent[1 - longer];
  return rectangle;
}

// m: twice the spacing between the columns of returns of `points` at their range
// (cuboids::acrossShortfall).
double columnSpacing(const ObjectView& object, const std::vector<std::size_t>& points) {
  cuboids::LevelledObject seen;
  seen.sensor = object.sensor.head<2>();
  seen.range = 1e9;
  for (const std::size_t i : points) {
    seen.points.push_back(object.points[i]);
    seen.range = std::min(seen.range, (object.points[i].head<2>() - seen.sensor).norm());
  }
  return cuboids::acrossShortfall(seen);
}

// Whether the scan saw rays pass through the gap of `cut` at body height, somewhere across the
// points (not within `kEdge` of their ends): the ground between two bodies, not the spacing of
// the rings over one roof, which lies behind the face nearer the sensor.
bool gapSeenEmpty(const ObjectView& object, const std::vector<std::size_t>& points,
                  const Cut& cut) {
  if (object.free_space == nullptr) {
    return false;
  }
  constexpr double kEdge = 0.1, kStep = 0.1;  // m
  const Eigen::Vector2d across(-cut.axis.y(), cut.axis.x());
  double from = 1e9, to = -1e9;
  for (const std::size_t i : points) {
    const double v = object.points[i].head<2>().dot(across);
    from = std::min(from, v), to = std::max(to, v);
  }
  for (double v = from + kEdge; v <= to - kEdge; v += kStep) {
    const Eigen::Vector2d place = cut.at * cut.axis + v * across;
    if (object.free_space->seenEmpty({place.x(), place.y(), 0.0})) {
      return true;
    }
  }
  return false;
}

void split(const ObjectView& object, std::vector<std::size_t> points,
           const std::vector<double>& heights, const VehicleSplitConfig& config,
           const LShapeConfig& lshape, int depth, std::vector<ObjectView>& pieces) {
  std::vector<Eigen::Vector2d> footprint;
  double top = 0.0;
  for (const std::size_t i : points) {
    footprint.push_back(object.points[i].head<2>());
    top = std::max(top, heights[i]);
  }
  // Trucks and buses are not cut, nor pieces already cut max_cuts deep.
  const bool may_cut = depth < config.max_cuts && top <= config.max_top;
  Rectangle rectangle = minimumAreaRectangle(footprint);
  // Cars seen in part show L-shapes (a front and a side) whose minimum-area rectangle lies
  // across them: two side by side, one further back, make one turned across both and no wider
  // than a car; a front and its neighbour's side, one turned so that a cut across it runs
  // diagonally through both. Along the L-shape's own edges, the rows' directions, they part.
  if (may_cut && config.edges_min_width > 0.0 && rectangle.length > config.max_width) {
    const Rectangle along_edges = lshapeFootprint(object, points, lshape);
    if (along_edges.width > config.edges_min_width) {
      rectangle = along_edges;
    }
  }
  const Eigen::Vector2d sight = (rectangle.centre - object.sensor.head<2>()).normalized();
  const Eigen::Vector2d length_axis(std::cos(rectangle.yaw), std::sin(rectangle.yaw));
  const Eigen::Vector2d width_axis(-length_axis.y(), length_axis.x());
  std::optional<Cut> cut;
  if (may_cut) {
    // Across the wider excess first: cars side by side, then nose to tail.
    if (rectangle.width > config.max_width) {
      cut = cutAlong(object, points, heights, width_axis, config);
      // Cars side by side seen from their fronts: the row is the longer side. It is cut first
      // where the width runs along the line of sight: successive rings spread apart over the
      // roofs and bonnets leave valleys there that lie inside one car.
      const auto along_sight = [&](const Eigen::Vector2d& axis) {
        return std::abs(axis.dot(sight)) > std::cos(config.sight_gap_deg * M_PI / 180.0);
      };
      if (!cut || (along_sight(width_axis) && !along_sight(length_axis))) {
        if (std::optional<Cut> across = cutAlong(object, points, heights, length_axis, config)) {
          cut = across;
        }
      }
    }
    if (!cut && rectangle.length > config.max_length) {
      cut = cutAlong(object, points, heights, length_axis, config);
    }
    // The footprint of two cars seen at a slant can make a minimum-area rectangle whose sides
    // follow neither car: then the deepest valley across any direction along which the points
    // span more than a car's width. A footprint wider than a car but within search_min_width
    // (a single car at a slant shows dips across its diagonals) is cut only at empty ground.
    const bool any_valley =
        rectangle.width > config.search_min_width || rectangle.length > config.max_length;
    if (!cut && config.search_step_deg > 0.0 &&
        (any_valley || rectangle.width > config.max_width)) {
      for (double deg = 0.0; deg < 180.0; deg += config.search_step_deg) {
        const double angle = rectangle.yaw + deg * M_PI / 180.0;
        const auto found = cutAlong(object, points, heights, {std::cos(angle), std::sin(angle)},
                                    config, config.max_width);
        if (found && (any_valley || found->gap) && (!cut || found->drop > cut->drop)) {
          cut = found;
        }
      }
    }
  }
  // One face of two bodies (two fronts side by side) is no wider than a car: it parts only
  // where the ground between them was seen, wider than the columns of returns are apart.
  if (may_cut && !cut && config.gap_min_length > 0.0 && rectangle.width <= config.max_width &&
      rectangle.length > config.gap_min_length && rectangle.length <= config.max_length) {
    std::optional<Cut> gap = cutAlong(object, points, heights, length_axis, config);
    if (gap && gap->gap) {
      // The columns' spacing (a sort of the bearings) only fills runs, so it is asked only where
      // min_gap alone left one.
      gap = cutAlong(object, points, heights, length_axis, config, 0.0,
                     columnSpacing(object, points));
    }
    if (gap && gap->gap && gapSeenEmpty(object, points, *gap)) {
      // Each side a front seen whole, not the sparse far end of one car's side.
      std::size_t near = 0;
      for (const std::size_t i : points) {
        near += object.points[i].head<2>().dot(gap->axis) < gap->at ? 1 : 0;
      }
      if (std::min(near, points.size() - near) >= config.gap_min_points) {
        cut = gap;
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
  split(object, std::move(near), heights, config, lshape, depth + 1, pieces);
  split(object, std::move(far), heights, config, lshape, depth + 1, pieces);
}

}  // namespace

std::vector<ObjectView> splitVehicles(const ObjectView& object, const VehicleSplitConfig& config,
                                      const LShapeConfig& lshape) {
  if (!config.enabled || object.points.size() < 3) {
    return {object};
  }
  double lowest = 1e9;
  for (const Eigen::Vector3d& p : object.points) {
    lowest = std::min(lowest, p.z());
  }
  std::vector<std::size_t> points(object.points.size());
  std::vector<double> heights(object.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = i;
    heights[i] = heightAbove(object, object.points[i], lowest);
  }
  std::vector<ObjectView> pieces;
  split(object, std::move(points), heights, config, lshape, 0, pieces);
  return pieces;
}

}  // namespace granular
