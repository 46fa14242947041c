#include "granular_core/cuboids/frame_cuboids.h"

#include <cmath>
#include <algorithm>
#include <chrono>
#include <optional>

#include "granular_core/cuboids/segment_views.h"
#include "granular_core/cuboids/vehicle_split.h"
#include "granular_core/parallel.h"

namespace granular {
std::vector<std::optional<double>> lentHeadings(
    const std::vector<std::optional<FittedCuboid>>& fitted,
    const std::vector<bool>& vehicle, const NeighbourHeadingConfig& config) {
  std::vector<std::optional<double>> lent(fitted.size());
  const double min_turn = config.min_turn_deg * M_PI / 180.0;
  const auto turn = [](double from, double to) { return std::abs(std::remainder(to - from, M_PI)); };
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    if (!fitted[i] || fitted[i]->heading_seen || !vehicle[i]) {
      continue;
    }
    const Eigen::Vector2d centre = fitted[i]->box.centre().head<2>();
    std::vector<double> near;
    for (std::size_t j = 0; j < fitted.size(); ++j) {
      if (j != i && fitted[j] && fitted[j]->heading_seen && vehicle[j] &&
          (fitted[j]->box.centre().head<2>() - centre).norm() <= config.radius) {
        near.push_back(fitted[j]->box.yaw());
      }
    }
    // The heading most neighbours share (within half min_turn), when all but a third do.
    std::size_t best = 0;
    for (const double heading : near) {
      const auto agree = static_cast<std::size_t>(std::count_if(
          near.begin(), near.end(), [&](double other) { return turn(heading, other) < min_turn / 2; }));
      if (agree > best) {
        best = agree;
        lent[i] = heading;
      }
    }
    if (best < 2 || 3 * best < 2 * near.size() || turn(fitted[i]->box.yaw(), *lent[i]) < min_turn) {
      lent[i].reset();
    }
  }
  return lent;
}

FrameCuboids fitFrameObjects(const std::vector<FrameObject>& objects, const CuboidFitter& fitter,
                             const FrameCuboidsOptions& options) {
  // The pieces to fit, each with its object; cut in the objects' order, so that the ids of
  // the pieces cut off do not depend on the threads.
  struct Piece {
    std::int64_t id;
    std::size_t object;
    ObjectView view;
  };
  std::vector<Piece> pieces;
  std::int64_t next_split_id = options.first_split_id;
  for (std::size_t o = 0; o < objects.size(); ++o) {
    if (options.evidence == nullptr) {
      pieces.push_back({objects[o].id, o, objects[o].view});
      continue;
    }
    std::vector<ObjectView> cars = splitVehicles(objects[o].view, options.split, options.lshape);
    for (std::size_t c = 0; c < cars.size(); ++c) {
      pieces.push_back({c == 0 ? objects[o].id : next_split_id++, o, std::move(cars[c])});
    }
  }

  FrameCuboids result;
  result.fitted_objects = pieces.size();
  result.milliseconds.assign(pieces.size(), 0.0);
  std::vector<std::optional<FittedCuboid>> fitted(pieces.size());
  // The vehicle decision runs in the same loop (measuring reads the frame's scan only); it is
  // not timed as the fit.
  std::vector<VehicleVerdict> verdicts(pieces.size(), VehicleVerdict::kVehicle);
  parallelFor(pieces.size(), options.threads, 1, [&](std::size_t i) {
    const auto begin = std::chrono::steady_clock::now();
    fitted[i] = fitter.fit(pieces[i].view);
    result.milliseconds[i] =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin)
            .count();
    if (options.evidence != nullptr && fitted[i]) {
      verdicts[i] =
          options.evidence->judge(options.evidence->measure(pieces[i].view.points, fitted[i]->box));
    }
  });
  if (options.evidence != nullptr && options.neighbour_heading.radius > 0.0) {
    // A heading left open takes the one its seen neighbours share, as fitted above (not as
    // lent here).
    std::vector<bool> vehicle(pieces.size());
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      vehicle[i] = verdicts[i] == VehicleVerdict::kVehicle;
    }
    const std::vector<std::optional<double>> lent =
        lentHeadings(fitted, vehicle, options.neighbour_heading);
    parallelFor(pieces.size(), options.threads, 1, [&](std::size_t i) {
      if (!lent[i]) {
        return;
      }
      ObjectView view = pieces[i].view;
      view.heading = lent[i];
      if (std::optional<FittedCuboid> turned = fitter.fit(view)) {
        fitted[i] = std::move(turned);
        verdicts[i] =
            options.evidence->judge(options.evidence->measure(view.points, fitted[i]->box));
      }
    });
  }
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    if (!fitted[i]) {
      ++result.without_cuboid;
    } else if (verdicts[i] != VehicleVerdict::kVehicle) {
      ++result.not_vehicles[verdictName(verdicts[i])];
    } else {
      result.kept.push_back({pieces[i].id, pieces[i].object, std::move(*fitted[i])});
    }
  }
  return result;
}

FrameCuboids fitSegmentCuboids(const Cloud& cloud, const ObjectSegmentation& segmentation,
                               const SegmentationStageConfig& segmentation_config,
                               const CuboidConfig& config, const CuboidFitter& fitter,
                               int threads) {
  const SegmentViews views(cloud, segmentation, segmentation_config, config.free_space);
  std::vector<FrameObject> objects(segmentation.segments.size());
  for (std::size_t s = 0; s < objects.size(); ++s) {
    objects[s] = {static_cast<std::int64_t>(s), views.view(s)};
  }
  // The decision needs the objects method's road plane.
  std::optional<VehicleEvidence> evidence;
  if (config.evidence.enabled && segmentation_config.method == SegmentationMethod::kObjects) {
    evidence.emplace(cloud, segmentation.ground.plane, config.evidence,
                     segmentation_config.objects.azimuth_step_deg);
  }
  FrameCuboidsOptions options;
  options.evidence = evidence ? &*evidence : nullptr;
  options.split = config.split;
  options.lshape = config.lshape;
  options.neighbour_heading = config.neighbour_heading;
  options.first_split_id = static_cast<std::int64_t>(objects.size());
  options.threads = threads;
  return fitFrameObjects(objects, fitter, options);
}

}  // namespace granular
