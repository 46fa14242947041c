#include "granular_core/registration/registration_config.h"

#include <stdexcept>
#include <vector>

#include "granular_core/text.h"

namespace granular {

std::map<std::string, RegistrationClassifierConfig> registrationPresets() {
  // Chosen on training drives only (scripts/tune_registration); config/classification.yaml and
  // docs/classification.md record the search.
  RegistrationClassifierConfig tuned;
  tuned.icp.max_iterations = 100;
  tuned.icp.max_correspondence_distance = 0.05;
  // Three iterations pairing up to 0.1 m first: a real car lies farther from the simulated
  // models than the simulator's own cars do.
  tuned.icp.coarse_iterations = 3;
  tuned.icp.coarse_correspondence_distance = 0.1;
  tuned.icp_nl = tuned.icp;
  tuned.ndt.resolution = 0.3;
  tuned.ndt.min_points_per_voxel = 3;
  tuned.source_min_z = 0.2;
  tuned.source_max_points = 100;
  // The tuned values on at most 50 points an object: for crowded frames online.
  RegistrationClassifierConfig fast = tuned;
  fast.source_max_points = 50;
  return {{"report", RegistrationClassifierConfig()}, {"tuned", tuned}, {"fast", fast}};
}

const RegistrationClassifierConfig& RegistrationPresets::preset(const std::string& name) const {
  const auto found = presets.find(name);
  if (found == presets.end()) {
    std::vector<std::string> known;
    for (const auto& [known_name, unused] : presets) {
      known.push_back(known_name);
    }
    throw std::invalid_argument("no preset '" + name + "' (known: " + joined(known) + ")");
  }
  return found->second;
}

}  // namespace granular
