#include "granular_core/models/model_config.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace granular {
namespace {

constexpr FilterStage kStages[] = {FilterStage::kPassThrough, FilterStage::kRadiusOutlier,
                                   FilterStage::kStatisticalOutlier, FilterStage::kVoxelGrid};

void require(bool condition, const std::string& what) {
  if (!condition) {
    throw std::invalid_argument(what);
  }
}

void requirePositive(double value, const std::string& field) {
  require(std::isfinite(value) && value > 0.0, field + " must be a positive number");
}

void validateChain(const FilterChainConfig& chain, const std::string& prefix) {
  for (std::size_t i = 0; i < chain.order.size(); ++i) {
    require(std::find(chain.order.begin(), chain.order.begin() + static_cast<long>(i),
                      chain.order[i]) == chain.order.begin() + static_cast<long>(i),
            prefix + "order: stage " + stageName(chain.order[i]) + " is listed twice");
  }
  const PassThroughConfig& band = chain.pass_through;
  require(std::isfinite(band.min_z) && std::isfinite(band.max_z) && band.min_z < band.max_z,
          prefix + "pass_through: min_z must be below max_z, both finite");
  requirePositive(chain.radius_outlier.radius, prefix + "radius_outlier.radius");
  require(chain.radius_outlier.min_neighbors >= 1,
          prefix + "radius_outlier.min_neighbors must be at least 1");
  require(chain.statistical_outlier.mean_k >= 1,
          prefix + "statistical_outlier.mean_k must be at least 1");
  require(std::isfinite(chain.statistical_outlier.stddev_mul),
          prefix + "statistical_outlier.stddev_mul must be finite");
  requirePositive(chain.voxel_grid.leaf_size, prefix + "voxel_grid.leaf_size");
}

}  // namespace

const char* methodName(ConcatenationMethod method) {
  return method == ConcatenationMethod::kIcp ? "icp" : "plain";
}

std::optional<ConcatenationMethod> methodFromName(const std::string& name) {
  if (name == "plain") {
    return ConcatenationMethod::kPlain;
  }
  if (name == "icp") {
    return ConcatenationMethod::kIcp;
  }
  return std::nullopt;
}

const char* stageName(FilterStage stage) {
  switch (stage) {
    case FilterStage::kPassThrough:
      return "pass_through";
    case FilterStage::kRadiusOutlier:
      return "radius_outlier";
    case FilterStage::kStatisticalOutlier:
      return "statistical_outlier";
    case FilterStage::kVoxelGrid:
      return "voxel_grid";
  }
  return "unknown";
}

std::optional<FilterStage> stageFromName(const std::string& name) {
  for (const FilterStage stage : kStages) {
    if (name == stageName(stage)) {
      return stage;
    }
  }
  return std::nullopt;
}

std::map<std::string, FilterChainOverride> defaultClassFilters() {
  const auto change = [](std::optional<double> max_z, double leaf_size) {
    FilterChainOverride result;
    result.max_z = max_z;
    result.leaf_size = leaf_size;
    return result;
  };
  // Leaves chosen on the simulated drive (objects/N10) for about 5,000 points per model with
  // plain concatenation; the voxel count is not monotonic in the leaf (faces of the simulated
  // meshes line up with the grid), hence the uneven values.
  return {{"BoxTruck", change(3.6, 0.075)}, {"Hatchback", change(std::nullopt, 0.045)},
          {"Jeep", change(std::nullopt, 0.07)}, {"SUV", change(std::nullopt, 0.065)},
          {"SchoolBus", change(3.4, 0.095)},    {"Sedan", change(std::nullopt, 0.055)}};
}

FilterChainConfig ModelBuildConfig::filtersFor(const std::string& label) const {
  FilterChainConfig chain = filters;
  const auto found = class_filters.find(label);
  if (found == class_filters.end()) {
    return chain;
  }
  const FilterChainOverride& change = found->second;
  chain.order = change.order.value_or(chain.order);
  chain.pass_through.min_z = change.min_z.value_or(chain.pass_through.min_z);
  chain.pass_through.max_z = change.max_z.value_or(chain.pass_through.max_z);
  chain.radius_outlier.radius = change.radius.value_or(chain.radius_outlier.radius);
  chain.radius_outlier.min_neighbors =
      change.min_neighbors.value_or(chain.radius_outlier.min_neighbors);
  chain.statistical_outlier.mean_k = change.mean_k.value_or(chain.statistical_outlier.mean_k);
  chain.statistical_outlier.stddev_mul =
      change.stddev_mul.value_or(chain.statistical_outlier.stddev_mul);
  chain.voxel_grid.leaf_size = change.leaf_size.value_or(chain.voxel_grid.leaf_size);
  return chain;
}

void validate(const ModelBuildConfig& config) {
  validateChain(config.filters, "filters.");
  for (const auto& [label, change] : config.class_filters) {
    require(!label.empty(), "class_filters: a class name is empty");
    validateChain(config.filtersFor(label), "class_filters." + label + ": ");
  }

  const IcpConfig& icp = config.icp;
  require(icp.max_iterations >= 1, "icp.max_iterations must be at least 1");
  requirePositive(icp.max_correspondence_distance, "icp.max_correspondence_distance");
  require(std::isfinite(icp.transformation_epsilon) && icp.transformation_epsilon >= 0.0,
          "icp.transformation_epsilon must be finite and not negative");
  require(std::isfinite(icp.euclidean_fitness_epsilon) && icp.euclidean_fitness_epsilon >= 0.0,
          "icp.euclidean_fitness_epsilon must be finite and not negative");
  requirePositive(icp.max_fitness, "icp.max_fitness");
  requirePositive(icp.max_translation, "icp.max_translation");
  require(std::isfinite(icp.max_rotation_deg) && icp.max_rotation_deg > 0.0 &&
              icp.max_rotation_deg <= 180.0,
          "icp.max_rotation_deg must be in (0, 180]");
  require(icp.min_points >= 3, "icp.min_points must be at least 3");
  require(std::isfinite(icp.target_leaf_size) && icp.target_leaf_size >= 0.0,
          "icp.target_leaf_size must be finite and not negative (0: no grid)");

  require(config.seed.objects_per_side >= 1, "seed.objects_per_side must be at least 1");

  const MeshConfig& mesh = config.mesh;
  require(mesh.normal_k >= 3, "mesh.normal_k must be at least 3");
  requirePositive(mesh.search_radius, "mesh.search_radius");
  requirePositive(mesh.mu, "mesh.mu");
  require(mesh.max_nearest_neighbors >= 3, "mesh.max_nearest_neighbors must be at least 3");
  require(mesh.min_angle_deg > 0.0 && mesh.min_angle_deg < mesh.max_angle_deg &&
              mesh.max_angle_deg < 180.0,
          "mesh: need 0 < min_angle_deg < max_angle_deg < 180");
  require(mesh.max_surface_angle_deg > 0.0 && mesh.max_surface_angle_deg <= 180.0,
          "mesh.max_surface_angle_deg must be in (0, 180]");
}

bool operator==(const PassThroughConfig& a, const PassThroughConfig& b) {
  return a.min_z == b.min_z && a.max_z == b.max_z;
}

bool operator==(const RadiusOutlierConfig& a, const RadiusOutlierConfig& b) {
  return a.radius == b.radius && a.min_neighbors == b.min_neighbors;
}

bool operator==(const StatisticalOutlierConfig& a, const StatisticalOutlierConfig& b) {
  return a.mean_k == b.mean_k && a.stddev_mul == b.stddev_mul;
}

bool operator==(const VoxelGridConfig& a, const VoxelGridConfig& b) {
  return a.leaf_size == b.leaf_size;
}

bool operator==(const FilterChainConfig& a, const FilterChainConfig& b) {
  return a.order == b.order && a.pass_through == b.pass_through &&
         a.radius_outlier == b.radius_outlier && a.statistical_outlier == b.statistical_outlier &&
         a.voxel_grid == b.voxel_grid;
}

bool operator==(const FilterChainOverride& a, const FilterChainOverride& b) {
  return a.order == b.order && a.min_z == b.min_z && a.max_z == b.max_z &&
         a.radius == b.radius && a.min_neighbors == b.min_neighbors && a.mean_k == b.mean_k &&
         a.stddev_mul == b.stddev_mul && a.leaf_size == b.leaf_size;
}

bool operator==(const IcpConfig& a, const IcpConfig& b) {
  return a.max_iterations == b.max_iterations &&
         a.max_correspondence_distance == b.max_correspondence_distance &&
         a.transformation_epsilon == b.transformation_epsilon &&
         a.euclidean_fitness_epsilon == b.euclidean_fitness_epsilon &&
         a.max_fitness == b.max_fitness && a.max_translation == b.max_translation &&
         a.max_rotation_deg == b.max_rotation_deg && a.min_points == b.min_points &&
         a.target_leaf_size == b.target_leaf_size;
}

bool operator==(const SeedConfig& a, const SeedConfig& b) {
  return a.objects_per_side == b.objects_per_side;
}

bool operator==(const MeshConfig& a, const MeshConfig& b) {
  return a.normal_k == b.normal_k && a.search_radius == b.search_radius && a.mu == b.mu &&
         a.max_nearest_neighbors == b.max_nearest_neighbors &&
         a.max_surface_angle_deg == b.max_surface_angle_deg &&
         a.min_angle_deg == b.min_angle_deg && a.max_angle_deg == b.max_angle_deg;
}

bool operator==(const ModelBuildConfig& a, const ModelBuildConfig& b) {
  return a.method == b.method && a.icp == b.icp && a.seed == b.seed && a.filters == b.filters &&
         a.class_filters == b.class_filters && a.mesh == b.mesh;
}

}  // namespace granular
