#pragma once

#include <filesystem>

#include <granular_core/segmentation/occupancy_segmentation.h>

namespace granular_ros {

/// Overlays the keys of a YAML segmentation config file (see config/segmentation.yaml:
/// cell_size, extent, height_threshold, link_cells, min_cells, min_points, max_length) on
/// `config`. Throws std::runtime_error naming the file and the key for an unreadable file, an
/// unknown key or a value of the wrong type. Ranges are checked by granular::validate.
void loadSegmentationConfig(const std::filesystem::path& file,
                            granular::SegmentationConfig& config);

}  // namespace granular_ros
