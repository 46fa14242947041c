#include "granular_core/models/model_config.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace granular {
namespace {

// `prefix` starts the messages of the checks between fields, `path` the field names.
void validateChain(const FilterChainConfig& chain, const std::string& prefix,
                   const std::string& path) {
  for (std::size_t i = 0; i < chain.order.size(); ++i) {
    config::require(
        std::find(chain.order.begin(), chain.order.begin() + static_cast<long>(i),
                  chain.order[i]) == chain.order.begin() + static_cast<long>(i),
        prefix + "order: stage " + stageName(chain.order[i]) + " is listed twice");
  }
  const PassThroughConfig& band = chain.pass_through;
  config::require(std::isfinite(band.min_z) &&
                      (!band.max_z || (std::isfinite(*band.max_z) && band.min_z < *band.max_z)),
                  prefix + "pass_through: min_z must be below max_z, both finite");
  config::validateFields(chain, path);
}

void validateChain(const FilterChainConfig& chain, const std::string& path) {
  validateChain(chain, path + ".", path);
}

}  // namespace

FilterChainOverrides defaultClassFilters() {
  // Leaves chosen on the simulated drive (objects/N10) for about 5,000 points per model with
  // plain concatenation; the voxel count is not monotonic in the leaf (faces of the simulated
  // meshes line up with the grid), hence the uneven values.
  FilterChainOverrides overrides;
  const auto leaf = [](double leaf_size) {
    return config::Json{{"voxel_grid", {{"leaf_size", leaf_size}}}};
  };
  overrides["BoxTruck"] = leaf(0.075);
  overrides["Hatchback"] = leaf(0.045);
  overrides["Jeep"] = leaf(0.07);
  overrides["SUV"] = leaf(0.065);
  overrides["SchoolBus"] = leaf(0.095);
  overrides["Sedan"] = leaf(0.055);
  return overrides;
}

std::optional<double> autoMaxZ(std::vector<double> heights) {
  if (heights.empty()) {
    return std::nullopt;
  }
  // Nearest rank.
  const std::size_t rank = (heights.size() * 95 + 99) / 100 - 1;
  std::nth_element(heights.begin(), heights.begin() + static_cast<std::ptrdiff_t>(rank),
                   heights.end());
  return kAutoMaxZFactor * heights[rank];
}

FilterChainConfig ModelBuildConfig::filtersFor(const std::string& label) const {
  return config::resolve(class_filters, label, filters, "class_filters");
}

void validate(const ModelBuildConfig& config) {
  config::require(config.min_objects >= 1, "min_objects: must be at least 1 object");
  config::require(config.min_points >= 1, "min_points: must be at least 1 point");
  validateChain(config.filters, "filters");
  for (const auto& [label, change] : config.class_filters.by_name) {
    config::require(!label.empty(), "class_filters: a class name is empty");
    FilterChainConfig chain;
    try {
      chain = config.filtersFor(label);
    } catch (const config::FieldError& error) {
      throw std::invalid_argument(error.what());
    }
    validateChain(chain, "class_filters." + label + ": ", "class_filters." + label);
  }
  config::validateFields(config.icp, "icp");
  config::validateFields(config.seed, "seed");
  const MeshConfig& mesh = config.mesh;
  config::validateFields(mesh, "mesh");
  config::require(mesh.min_angle_deg < mesh.max_angle_deg,
                  "mesh: need 0 < min_angle_deg < max_angle_deg < 180");
}

}  // namespace granular
