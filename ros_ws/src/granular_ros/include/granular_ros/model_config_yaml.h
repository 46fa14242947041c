#pragma once

#include <filesystem>

#include <granular_core/models/model_config.h>

namespace granular_ros {

/// Overlays the keys of a YAML models config file (see config/models.yaml: `method`, `seed`,
/// `icp`, `filters`, `class_filters`, `mesh`) on `config`; keys the file leaves out keep their
/// values, and a class under `class_filters` has its listed values merged into that class's
/// override. Throws std::runtime_error naming the file and the key path (e.g.
/// `filters.voxel_grid.leaf_size`) for an unreadable file, an unknown key, or a value of the
/// wrong type or shape. Ranges are checked by granular::validate.
void loadModelConfig(const std::filesystem::path& file, granular::ModelBuildConfig& config);

}  // namespace granular_ros
