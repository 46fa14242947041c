// A frame's objects to cuboids, the same way offline (fit_cuboids) and online (segment_cloud):
// touching cars cut apart, a cuboid fitted to each, and the zero-shot vehicle decision on it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/cuboids/vehicle_evidence.h"
#include "granular_core/point_types.h"
#include "granular_core/segmentation/object_segmentation.h"

namespace granular {

/// One object of a frame to fit, and the id its cuboid gets.
struct FrameObject {
  std::int64_t id = 0;
  ObjectView view;
};

/// A cuboid kept, and where it came from.
struct FrameCuboid {
  /// Its object's id; a piece cut off an object after its first takes the next id from
  /// FrameCuboidsOptions::first_split_id on, in the objects' order.
  std::int64_t id = 0;
  std::size_t object = 0;  ///< index of its object among the objects given
  FittedCuboid cuboid;
};

/// What became of a frame's objects.
struct FrameCuboids {
  std::vector<FrameCuboid> kept;  ///< in the objects' order, a cut object's pieces in turn
  /// Objects given to the fitter (the pieces of a cut object each), and per object the
  /// milliseconds in CuboidFitter::fit (the vehicle decision not included).
  std::size_t fitted_objects = 0;
  std::vector<double> milliseconds;
  /// Objects the fitter gave no cuboid (too few points above the road).
  std::size_t without_cuboid = 0;
  /// Objects the vehicle decision judged no vehicle, by verdict name (verdictName).
  std::map<std::string, std::size_t> not_vehicles;
};

struct FrameCuboidsOptions {
  /// The frame's zero-shot vehicle decision; null: every cuboid kept, no object cut.
  const VehicleEvidence* evidence = nullptr;
  /// The cutting of touching cars (CuboidConfig::split), done where `evidence` is given.
  VehicleSplitConfig split;
  /// The L-shape (CuboidConfig::lshape) whose edges tell two staggered cars in one footprint.
  LShapeConfig lshape;
  /// Headings lent by neighbours (CuboidConfig::neighbour_heading), where `evidence` is given.
  NeighbourHeadingConfig neighbour_heading;
  /// The id of the first piece cut off an object after its first piece.
  std::int64_t first_split_id = 0;
  /// Threads fitting the objects; 0: every core.
  int threads = 0;
};

/// Per cuboid of `fitted` judged a vehicle (`vehicle`) whose heading was left open
/// (FittedCuboid::heading_seen false), the heading (rad) its neighbours lend it: that of the
/// vehicles whose heading was seen within config.radius of its centre, when at least two of
/// them share it (within half config.min_turn_deg) and no more than a third do not, and it turns
/// the cuboid at least config.min_turn_deg (modulo pi). nullopt for the others.
std::vector<std::optional<double>> lentHeadings(
    const std::vector<std::optional<FittedCuboid>>& fitted, const std::vector<bool>& vehicle,
    const NeighbourHeadingConfig& config);

/// Fits a cuboid to each of `objects` with `fitter`, over the threads; with a vehicle decision,
/// each object is first cut into cars (splitVehicles), a piece whose heading was left open is
/// fitted again along the heading its neighbours lend it (lentHeadings), and each piece's
/// cuboid is kept only when judged a vehicle. Objects without a cuboid are dropped and counted.
FrameCuboids fitFrameObjects(const std::vector<FrameObject>& objects, const CuboidFitter& fitter,
                             const FrameCuboidsOptions& options);

/// The box-free path's cuboids of one frame, as fit_cuboids (without a classifier) and the
/// segment_cloud node make them: the segments of `segmentation` (of `cloud`, by `segmentation_
/// config`, whose azimuth step is the sensor's) as SegmentViews, each with the id of its
/// index; with the objects method and config.evidence.enabled, cut, fitted and judged by the
/// zero-shot vehicle decision measured on `cloud` (pieces cut off numbered after the
/// segments), otherwise every segment's cuboid kept. `config` must be validated.
FrameCuboids fitSegmentCuboids(const Cloud& cloud, const ObjectSegmentation& segmentation,
                               const SegmentationStageConfig& segmentation_config,
                               const CuboidConfig& config, const CuboidFitter& fitter,
                               int threads = 0);

}  // namespace granular
