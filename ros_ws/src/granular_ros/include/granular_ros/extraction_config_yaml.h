#pragma once

#include <filesystem>

#include <granular_core/extraction/extraction_config.h>

namespace granular_ros {

/// Overlays the keys of a YAML extraction config file (see config/extraction.yaml: `padding`,
/// `n_thresh`, `labels`) on `config`; keys the file leaves out keep their values. Throws
/// std::runtime_error naming the file and the key for an unreadable file, an unknown key, or a
/// value of the wrong type or shape. Ranges are checked by granular::validate.
void loadExtractionConfig(const std::filesystem::path& file, granular::ExtractionConfig& config);

}  // namespace granular_ros
