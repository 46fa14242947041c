#pragma once

#include <cstddef>
#include <vector>

#include "granular_core/point_types.h"
#include "granular_core/models/model_config.h"

namespace granular {

/// Ground removal (report 5.3.1): the points with min_z <= z <= max_z, in input order.
ModelCloud passThroughZ(const ModelCloud& cloud, const PassThroughConfig& config);

/// Radius outlier removal (5.3.2, pcl::RadiusOutlierRemoval): the points with at least
/// config.min_neighbors other points within config.radius, in input order.
ModelCloud removeRadiusOutliers(const ModelCloud& cloud, const RadiusOutlierConfig& config);

/// Statistical outlier removal (5.3.3, pcl::StatisticalOutlierRemoval): drops the points whose
/// mean distance to their mean_k nearest neighbours is more than stddev_mul standard
/// deviations above the cloud's mean of that distance. A cloud of mean_k points or fewer has no
/// statistics to speak of and is returned unchanged.
ModelCloud removeStatisticalOutliers(const ModelCloud& cloud,
                                     const StatisticalOutlierConfig& config);

/// Voxel grid subsampling (5.3.4, pcl::VoxelGrid): one point, the centroid, per occupied cubic
/// voxel of edge leaf_size; voxels are aligned to multiples of leaf_size.
ModelCloud voxelGrid(const ModelCloud& cloud, const VoxelGridConfig& config);

/// Runs one stage with its parameters from `chain`.
ModelCloud applyStage(const ModelCloud& cloud, FilterStage stage, const FilterChainConfig& chain);

/// The number of points left after one stage.
struct StageResult {
  FilterStage stage;
  std::size_t points;
};

/// Runs the stages of chain.order on `raw`, in that order; `stages`, when given, receives the
/// points left after each. An empty cloud passes through every stage empty.
ModelCloud applyFilterChain(const ModelCloud& raw, const FilterChainConfig& chain,
                            std::vector<StageResult>* stages = nullptr);

}  // namespace granular
