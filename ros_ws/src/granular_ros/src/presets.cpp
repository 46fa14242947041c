#include "granular_ros/presets.h"

#include <stdexcept>

#include "granular_ros/command_line.h"
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

std::string presetHelp() {
  const auto presets = granular::registrationPresets();
  const granular::RegistrationClassifierConfig& report = presets.at("report");
  const granular::RegistrationClassifierConfig& tuned = presets.at("tuned");
  return "parameter set: report (the report's values: ICP " + shown(report.icp.max_iterations) +
         " iteration, " + shown(report.icp.max_correspondence_distance) +
         " m; NDT resolution " + shown(report.ndt.resolution) + " m, " +
         shown(report.ndt.max_iterations) +
         " iterations), tuned (chosen on training drives; ICP and ICP-NL first pair points up "
         "to " + shown(tuned.icp.coarse_correspondence_distance) + " m for " +
         shown(tuned.icp.coarse_iterations) + " iterations; at most " +
         shown(tuned.source_max_points) + " points an object) or fast (tuned on at most " +
         shown(presets.at("fast").source_max_points) + " points); default " + kDefaultPreset;
}

}  // namespace granular_ros
