#include "granular_core/models/filter_chain.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include <pcl/common/common.h>
#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>

namespace granular {
namespace {

// PCL filters read through a shared pointer; the copy is small next to the filtering.
ModelCloud::ConstPtr shared(const ModelCloud& cloud) {
  return ModelCloud::ConstPtr(new ModelCloud(cloud));
}

}  // namespace

ModelCloud passThroughZ(const ModelCloud& cloud, const PassThroughConfig& config) {
  if (cloud.empty()) {
    return cloud;
  }
  if (!config.max_z) {
    throw std::logic_error("pass_through.max_z is auto: buildClassModel works it out first");
  }
  // By hand rather than pcl::PassThrough, whose float limits would move the band's edges by
  // the rounding of min_z and max_z.
  ModelCloud kept;
  kept.reserve(cloud.size());
  for (const pcl::PointXYZ& point : cloud.points) {
    if (point.z >= config.min_z && point.z <= *config.max_z) {
      kept.push_back(point);
    }
  }
  return kept;
}

ModelCloud removeRadiusOutliers(const ModelCloud& cloud, const RadiusOutlierConfig& config) {
  ModelCloud kept;
  if (cloud.empty()) {
    return kept;
  }
  pcl::RadiusOutlierRemoval<pcl::PointXYZ> filter;
  filter.setInputCloud(shared(cloud));
  filter.setRadiusSearch(config.radius);
  filter.setMinNeighborsInRadius(config.min_neighbors);
  filter.filter(kept);
  return kept;
}

ModelCloud removeStatisticalOutliers(const ModelCloud& cloud,
                                     const StatisticalOutlierConfig& config) {
  if (cloud.size() <= static_cast<std::size_t>(config.mean_k)) {
    return cloud;
  }
  ModelCloud kept;
  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> filter;
  filter.setInputCloud(shared(cloud));
  filter.setMeanK(config.mean_k);
  filter.setStddevMulThresh(config.stddev_mul);
  filter.filter(kept);
  return kept;
}

ModelCloud voxelGrid(const ModelCloud& cloud, const VoxelGridConfig& config) {
  ModelCloud kept;
  if (cloud.empty()) {
    return kept;
  }
  // PCL's voxel grid gives its input back unfiltered, with only a console warning, when the
  // voxels would outnumber a 32-bit index; say so instead.
  Eigen::Vector4f low, high;
  pcl::getMinMax3D(cloud, low, high);
  const auto leaf_f = static_cast<float>(config.leaf_size);
  double voxels = 1.0;  // as a double: tiny leaves overflow 64 bits
  for (int axis = 0; axis < 3; ++axis) {
    voxels *= std::floor(static_cast<double>((high[axis] - low[axis]) * (1.0f / leaf_f))) + 1.0;
  }
  if (voxels > std::numeric_limits<std::int32_t>::max()) {
    const Eigen::Vector3f span = (high - low).head<3>();
    const double smallest = std::cbrt(static_cast<double>(span.x()) * span.y() * span.z() /
                                      std::numeric_limits<std::int32_t>::max());
    throw std::invalid_argument(
        "voxel_grid.leaf_size " + std::to_string(config.leaf_size) + " m is too small for a cloud of " +
        std::to_string(span.x()) + " x " + std::to_string(span.y()) + " x " +
        std::to_string(span.z()) + " m (PCL's voxel grid would skip itself); use at least " +
        std::to_string(smallest * 1.01) + " m");
  }
  pcl::VoxelGrid<pcl::PointXYZ> filter;
  filter.setInputCloud(shared(cloud));
  const auto leaf = static_cast<float>(config.leaf_size);
  filter.setLeafSize(leaf, leaf, leaf);
  filter.filter(kept);
  return kept;
}

ModelCloud applyStage(const ModelCloud& cloud, FilterStage stage,
                      const FilterChainConfig& chain) {
  switch (stage) {
    case FilterStage::kPassThrough:
      return passThroughZ(cloud, chain.pass_through);
    case FilterStage::kRadiusOutlier:
      return removeRadiusOutliers(cloud, chain.radius_outlier);
    case FilterStage::kStatisticalOutlier:
      return removeStatisticalOutliers(cloud, chain.statistical_outlier);
    case FilterStage::kVoxelGrid:
      return voxelGrid(cloud, chain.voxel_grid);
  }
  return cloud;
}

ModelCloud applyFilterChain(const ModelCloud& raw, const FilterChainConfig& chain,
                            std::vector<StageResult>* stages) {
  ModelCloud cloud = raw;
  for (const FilterStage stage : chain.order) {
    cloud = applyStage(cloud, stage, chain);
    if (stages != nullptr) {
      stages->push_back({stage, cloud.size()});
    }
  }
  return cloud;
}

}  // namespace granular
