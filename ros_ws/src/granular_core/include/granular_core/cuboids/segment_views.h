// The box-free path's objects as the cuboid fitters see them.
#pragma once

#include <cstddef>
#include <optional>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/cuboids/polar_returns.h"
#include "granular_core/segmentation/object_segmentation.h"

namespace granular {

/// The segments of one frame as ObjectViews: each segment's points, and, for the objects method,
/// the ground it stood on, the segmentation's height cap and the frame's FreeSpace. What
/// fit_cuboids, evaluate_segmentation --cuboids and segment_cloud fit cuboids to. The views
/// point into this object, which must outlive them; `cloud` and `segmentation` are read here only.
class SegmentViews {
 public:
  SegmentViews(const Cloud& cloud, const ObjectSegmentation& segmentation,
               const SegmentationStageConfig& config, const FreeSpaceConfig& free_space);
  /// The same with the frame's returns about the sensor already measured (`scan`, above
  /// segmentation.ground.plane), which the FreeSpace reads instead of the cloud.
  SegmentViews(const Cloud& cloud, const ObjectSegmentation& segmentation,
               const SegmentationStageConfig& config, const FreeSpaceConfig& free_space,
               const PolarReturns& scan);
  /// The view of segmentation.segments[segment].
  ObjectView view(std::size_t segment) const;

 private:
  const Cloud& cloud_;
  const ObjectSegmentation& segmentation_;
  std::optional<double> height_cap_;  // set for the objects method, which has a ground
  std::optional<FreeSpace> free_space_;
};

}  // namespace granular
