#include "granular_core/cuboids/cuboid_config.h"

#include <algorithm>
#include <stdexcept>

namespace granular {

std::map<std::string, SizePrior> defaultSizePriors() {
  return {
      // KITTI's training labels: mean length, width and height per class (as tabulated by
      // Frustum PointNets, Qi et al. 2018).
      {"Car", {3.88, 1.63, 1.53}},
      {"Van", {5.07, 1.90, 2.21}},
      {"Truck", {10.14, 2.59, 3.25}},
      // The simulator's class meshes (granular_tools/simulation/meshes.py); its instances are
      // scaled by up to size_variation (5%) on each axis.
      {"Sedan", {4.60, 1.82, 1.45}},
      {"SUV", {4.80, 1.94, 1.80}},
      {"Hatchback", {4.10, 1.78, 1.50}},
      {"Jeep", {4.42, 1.96, 1.85}},
      {"BoxTruck", {7.20, 2.40, 3.30}},
      {"SchoolBus", {11.00, 2.50, 3.10}},
  };
}

RegistrationClassifierConfig ModelFitConfig::defaultRegistration() {
  RegistrationClassifierConfig registration;
  registration.icp.max_iterations = 20;
  registration.icp.max_correspondence_distance = 0.5;
  registration.icp.transformation_epsilon = 1e-6;
  registration.icp_nl = registration.icp;
  registration.ndt.resolution = 0.5;
  registration.ndt.min_points_per_voxel = 3;
  registration.ndt.step_size = 0.1;
  registration.ndt.max_iterations = 20;
  registration.source_min_z = 0.2;
  return registration;
}

void validate(const CuboidConfig& config) {
  config::validateFields(config);
  config::require(config.points.min_height < config.points.max_height,
                  "points.min_height must be below points.max_height");
  config::require(config.free_space.body_min < config.free_space.body_max,
                  "free_space.body_min must be below free_space.body_max");
  config::require(config.lshape.fine_step_deg <= config.lshape.coarse_step_deg,
                  "lshape.fine_step_deg must not exceed lshape.coarse_step_deg");
  config::require(config.free_space.bin_deg == 0.0 || config.free_space.bin_deg >= 0.01,
                  "free_space.bin_deg must be 0 (not looked at) or at least 0.01 deg");
  config::require(config.free_space.occupied_cell == 0.0 || config.free_space.occupied_cell >= 0.01,
                  "free_space.occupied_cell must be 0 (not looked at) or at least 0.01 m");
  config::require(config.free_space.occupied_cell == 0.0 ||
                      config.free_space.occupied_range <= 2000.0 * config.free_space.occupied_cell,
                  "free_space.occupied_range must be at most 2000 occupied_cell (a bit per cell "
                  "of a square twice as wide)");
  config::require(config.split.search_step_deg == 0.0 || config.split.search_step_deg >= 0.1,
                  "split.search_step_deg must be 0 (the rectangle's sides only) or at least 0.1 deg");
  config::require(config.model.headings == 2 || config.model.headings == 4,
                  "model.headings must be 2 or 4");
  for (const std::string& name : config.geometric.classes) {
    config::require(config.priors.count(name) > 0,
                    "geometric.classes: no prior for '" + name + "' in priors");
  }
}

}  // namespace granular
