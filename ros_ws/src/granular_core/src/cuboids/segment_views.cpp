#include "granular_core/cuboids/segment_views.h"

namespace granular {

SegmentViews::SegmentViews(const Cloud& cloud, const ObjectSegmentation& segmentation,
                           const SegmentationStageConfig& config,
                           const FreeSpaceConfig& free_space)
    : cloud_(cloud), segmentation_(segmentation) {
  if (config.method == SegmentationMethod::kObjects) {
    height_cap_ = config.objects.max_height;
    free_space_.emplace(cloud, segmentation.ground.plane, free_space);
  }
}

SegmentViews::SegmentViews(const Cloud& cloud, const ObjectSegmentation& segmentation,
                           const SegmentationStageConfig& config,
                           const FreeSpaceConfig& free_space, const PolarReturns& scan)
    : cloud_(cloud), segmentation_(segmentation) {
  if (config.method == SegmentationMethod::kObjects) {
    height_cap_ = config.objects.max_height;
    free_space_.emplace(scan, free_space);
  }
}

ObjectView SegmentViews::view(std::size_t segment) const {
  ObjectView view;
  const std::vector<std::size_t>& indices = segmentation_.segments.at(segment).indices;
  view.points.reserve(indices.size());
  for (const std::size_t i : indices) {
    view.points.emplace_back(cloud_[i].x, cloud_[i].y, cloud_[i].z);
  }
  if (height_cap_) {
    view.ground = segmentation_.ground.plane;
    view.height_cap = height_cap_;
    view.free_space = &*free_space_;
  }
  return view;
}

}  // namespace granular
