#pragma once

#include <filesystem>
#include <map>
#include <string>

#include <granular_core/classification/registration_config.h>

namespace granular_ros {

/// Overlays the presets of a YAML classification config file (see config/classification.yaml:
/// `presets: {<name>: {icp, icp_nl, ndt, source_min_z}}`) on `presets`: a preset already there
/// keeps the values the file leaves out; a new one starts from the defaults (the report's
/// values). `source_min_z: null` unsets it. Throws std::runtime_error naming the file and the
/// key path (e.g. `presets.tuned.ndt.resolution`) for an unreadable file, an unknown key, or
/// a value of the wrong type. Ranges are checked by granular::validate.
void loadRegistrationPresets(const std::filesystem::path& file,
                             std::map<std::string, granular::RegistrationClassifierConfig>& presets);

}  // namespace granular_ros
