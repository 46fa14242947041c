#include "granular_ros/presets.h"

#include <stdexcept>

#include "granular_ros/config_file.h"

namespace granular_ros {

granular::RegistrationClassifierConfig resolvePreset(
    const std::optional<std::filesystem::path>& file, const std::string& name) {
  granular::RegistrationPresets presets;
  if (file) {
    loadConfigFile(*file, presets);
  }
  const granular::RegistrationClassifierConfig& preset = presets.preset(name);
  try {
    granular::validate(preset);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument("invalid configuration (preset " + name + "): " + error.what());
  }
  return preset;
}

}  // namespace granular_ros
