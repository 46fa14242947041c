#include "granular_core/cuboids/frame_cuboids.h"

#include <chrono>
#include <optional>

#include "granular_core/cuboids/segment_views.h"
#include "granular_core/cuboids/vehicle_split.h"
#include "granular_core/parallel.h"

namespace granular {

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
    std::vector<ObjectView> cars = splitVehicles(objects[o].view, options.split);
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
  options.first_split_id = static_cast<std::int64_t>(objects.size());
  options.threads = threads;
  return fitFrameObjects(objects, fitter, options);
}

}  // namespace granular
