#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "levelled_object.h"

namespace granular {
namespace {

// The prior of `classes` whose height is nearest `height`; the first on a tie.
const SizePrior* nearestPrior(const CuboidConfig& config, double height) {
  const SizePrior* best = nullptr;
  double best_gap = std::numeric_limits<double>::infinity();
  for (const std::string& name : config.geometric.classes) {
    const SizePrior& prior = config.priors.at(name);
    const double gap = std::abs(prior.height - height);
    if (gap < best_gap) {
      best_gap = gap;
      best = &prior;
    }
  }
  return best;
}

// Whether an object whose top is `height` may be taller than seen: `capped` (the points were
// cut at `height`), or `height` is above cut_top_above and more than cap_reach lower than its
// nearest prior's (the sensor's highest ring may have passed under the roof).
bool mayBeTaller(const CuboidConfig& config, const SizePrior* nearest, double height,
                 bool capped) {
  return capped || (height > config.geometric.cut_top_above && nearest != nullptr &&
                    nearest->height > height + config.geometric.cap_reach);
}

// The prior nearest `height`; for an object that may be taller, the shortest of those at least
// `height` high and longer than `length` seen, when there is one.
const SizePrior* choosePrior(const CuboidConfig& config, double height, bool may_be_taller,
                             double length) {
  const SizePrior* best = nearestPrior(config, height);
  if (may_be_taller) {
    for (const std::string& name : config.geometric.classes) {
      const SizePrior& prior = config.priors.at(name);
      if (prior.height >= height &&
          prior.length + config.geometric.width_tolerance >= length &&
          (best->height < height || prior.length < best->length)) {
        best = &prior;
      }
    }
  }
  return best;
}

// The shortest prior of `classes` at least `height` high and longer than `than`, if any.
const SizePrior* nextLongerPrior(const CuboidConfig& config, double height,
                                 const SizePrior& than) {
  const SizePrior* longer = nullptr;
  for (const std::string& name : config.geometric.classes) {
    const SizePrior& prior = config.priors.at(name);
    if (prior.height >= height && prior.length > than.length &&
        (longer == nullptr || prior.length < longer->length)) {
      longer = &prior;
    }
  }
  return longer;
}

// How many steps of `step` along `grown`'s length axis, from `skip` beyond its end away from
// `sensor` up to `length` from its other end, hold a place seen occupied anywhere across its
// width (and one `cell` either side): the body of a longer vehicle continuing past the grown
// end (not the last `skip` of one a little longer than its prior).
std::size_t occupiedBeyond(const AxisRectangle& grown, const Eigen::Vector2d& sensor,
                           int length_axis, double length, double skip, double step, double cell,
                           const std::function<bool(const Eigen::Vector2d&)>& occupied) {
  const int across = 1 - length_axis;
  const bool away_is_max =
      grown.coordinates(sensor)[length_axis] < (grown.min + grown.max)[length_axis] / 2;
  std::size_t steps = 0;
  const double extra = length - grown.extent()[length_axis];
  for (double along = skip + step / 2; along < extra; along += step) {
    Eigen::Vector2d place;
    place[length_axis] =
        away_is_max ? grown.max[length_axis] + along : grown.min[length_axis] - along;
    for (double v = grown.min[across] - cell; v <= grown.max[across] + cell; v += cell / 2) {
      place[across] = v;
      if (occupied(grown.point(place))) {
        ++steps;
        break;
      }
    }
  }
  return steps;
}

// Whether the object is a person on foot or on two wheels (GeometricFitConfig::rider_width):
// tall enough, and narrow above the rider's waist along both axes of `rectangle`.
bool isRider(const cuboids::LevelledObject& object, const AxisRectangle& rectangle,
             const GeometricFitConfig& config) {
  return object.top >= config.rider_min_top &&
         cuboids::extentAbove(object, rectangle, config.rider_above * object.top).maxCoeff() <=
             config.rider_width;
}

// `heading` (rad, sensor frame) as a heading in `object`'s levelled frame.
double levelledHeading(const cuboids::LevelledObject& object, double heading) {
  const Eigen::Vector3d along =
      object.levelling.linear() * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
  return std::atan2(along.y(), along.x());
}

}  // namespace

GeometricCuboidFitter::GeometricCuboidFitter(const CuboidConfig& config) : config_(config) {
  validate(config_);
}

std::optional<FittedCuboid> GeometricCuboidFitter::fit(const ObjectView& object) const {
  const std::optional<cuboids::LevelledObject> levelled =
      cuboids::levelObject(object, config_.points);
  if (!levelled) {
    return std::nullopt;
  }
  AxisRectangle rectangle = object.heading ? cuboids::enclosingRectangle(
                                                 *levelled, levelledHeading(*levelled, *object.heading))
                                           : cuboids::lshapeRectangle(*levelled, config_.lshape);
  const Eigen::Vector2d seen = rectangle.extent();
  const double cap_reach = cuboids::spanAt(levelled->range, config_.geometric.cap_reach,
                                           config_.geometric.cap_reach_deg);
  const bool capped = object.height_cap && levelled->top >= *object.height_cap - cap_reach;
  const bool may_be_taller =
      mayBeTaller(config_, nearestPrior(config_, levelled->top), levelled->top, capped);
  const SizePrior* prior =
      seen.maxCoeff() >= config_.geometric.min_extent &&
              !isRider(*levelled, rectangle, config_.geometric)
          ? choosePrior(config_, levelled->top, may_be_taller, seen.maxCoeff())
          : nullptr;
  const int longer = seen.x() >= seen.y() ? 0 : 1;
  Eigen::Vector2d body = cuboids::bodyExtent(*levelled, rectangle);
  if (prior != nullptr && !object.heading && config_.lshape.face_closeness_d0 > 0.0 &&
      body.maxCoeff() <= prior->width + config_.geometric.width_tolerance) {
    // Seen as one face (an end), a bump on it (a spare wheel, a rounded nose) can outvote the
    // face's returns: where a criterion tolerating it turns the rectangle far, it is taken.
    LShapeConfig tolerant = config_.lshape;
    tolerant.closeness_d0 = config_.lshape.face_closeness_d0;
    const AxisRectangle face = cuboids::lshapeRectangle(*levelled, tolerant);
    if (std::abs(std::remainder(face.heading - rectangle.heading, M_PI / 2)) >=
        config_.lshape.face_min_turn_deg * M_PI / 180.0) {
      rectangle = face;
      body = cuboids::bodyExtent(*levelled, rectangle);
    }
  }
  // Seen longer than the class is wide, the length can only lie along the longer side.
  const bool heading_seen =
      prior == nullptr || body.maxCoeff() > prior->width + config_.geometric.width_tolerance;
  int length_axis =
      object.heading   ? 0
      : prior != nullptr ? cuboids::lengthAxis(body, prior->width, config_.geometric.width_tolerance,
                                             rectangle.coordinates(rectangle.centre() -
                                                                   levelled->sensor),
                                             [&] { return cuboids::acrossShortfall(*levelled); })
                       : longer;
  if (prior != nullptr) {
    // Outside the block below: seen_empty, used after it, refers to them.
    const Eigen::Isometry3d to_sensor = levelled->levelling.inverse();
    const double body_height = (config_.free_space.body_min + config_.free_space.body_max) / 2;
    // A levelled place at body height, in the sensor frame the scan was binned in.
    const auto at_body_height = [&](const Eigen::Vector2d& place) {
      return to_sensor * Eigen::Vector3d(place.x(), place.y(), body_height);
    };
    cuboids::SeenEmpty seen_empty;
    if (object.free_space != nullptr) {
      seen_empty = [&](const Eigen::Vector2d& place) {
        return object.free_space->seenEmpty(at_body_height(place));
      };
      const auto refutes = [&](const Eigen::Vector2d& place) {
        const Eigen::Vector3d at = at_body_height(place);
        return object.free_space->seenEmpty(at) || object.free_space->seenOccupied(at);
      };
      // Seen no longer than a car is wide, either side may be its length: not the one whose
      // body would stand where the scan saw nothing or another object.
      if (config_.free_space.refuted_margin > 0 && !object.heading &&
          body.maxCoeff() <= prior->width + config_.geometric.width_tolerance) {
        const auto refuted = [&](int axis, std::size_t enough) {
          return cuboids::refutedGrowth(rectangle, levelled->sensor, axis, prior->length,
                                        prior->width, refutes, config_.free_space.step, enough);
        };
        // The chosen side's count matters only up to the other's plus the margin.
        const std::size_t other = refuted(1 - length_axis, std::numeric_limits<std::size_t>::max());
        const std::size_t enough = other + config_.free_space.refuted_margin;
        if (refuted(length_axis, enough) >= enough) {
          length_axis = 1 - length_axis;
        }
      }
    }
    const AxisRectangle seen_rectangle = rectangle;
    rectangle = cuboids::grownFromSeenCorner(rectangle, levelled->sensor, length_axis,
                                             prior->length, prior->width, seen_empty,
                                             config_.free_space.step, config_.free_space.inset);
    // A bus cut at the height cap and seen end on looks like a box truck; where the scan shows
    // its body going on past the truck's length, it is the longer vehicle.
    const SizePrior* longer = may_be_taller && object.free_space != nullptr &&
                                      config_.geometric.longer_occupied_steps > 0
                                  ? nextLongerPrior(config_, levelled->top, *prior)
                                  : nullptr;
    if (longer != nullptr) {
      const auto occupied = [&](const Eigen::Vector2d& place) {
        return object.free_space->seenOccupied(at_body_height(place));
      };
      if (occupiedBeyond(rectangle, levelled->sensor, length_axis, longer->length,
                         config_.geometric.width_tolerance, config_.free_space.step,
                         config_.free_space.occupied_cell,
                         occupied) >= config_.geometric.longer_occupied_steps) {
        prior = longer;
        rectangle = cuboids::grownFromSeenCorner(seen_rectangle, levelled->sensor, length_axis,
                                                 prior->length, prior->width, seen_empty,
                                                 config_.free_space.step,
                                                 config_.free_space.inset);
      }
    }
  }
  const double height = prior != nullptr && levelled->points.size() < config_.geometric.height_points
                            ? prior->height
                            : levelled->top;
  // A rectangle of points in one cell has no extent: it gets one cell's.
  const Eigen::Vector2d extent = rectangle.extent().cwiseMax(config_.lshape.cell);
  const double yaw = rectangle.heading + (length_axis == 1 ? M_PI / 2 : 0.0);
  FittedCuboid cuboid{
      kUnknownLabel, 1.0,
      cuboids::sensorBox(levelled->levelling, rectangle.centre(), yaw,
                         Eigen::Vector3d(extent[length_axis], extent[1 - length_axis],
                                         std::max(height, config_.lshape.cell))),
      levelled->points.size(), heading_seen && !object.heading};
  return cuboid;
}

}  // namespace granular
