#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

namespace granular {

/// m: the distances at which a registration's inlier shares are measured. From a few
/// centimetres (the scan's noise, the models' voxels) to 0.2 m (a body panel that sits farther
/// in or out than the model's).
inline constexpr std::array<double, 4> kInlierRadii{0.03, 0.06, 0.1, 0.2};

/// Per kInlierRadii radius, the share of an aligned object's points whose nearest model point
/// is closer than it. The fitness is a mean, dominated by the farthest points; how many points
/// lie close to the model, at several distances, says how much of the object the model
/// explains (svm_fitness's features beside the fitness).
using InlierShares = std::array<float, kInlierRadii.size()>;

/// The `r`-th radius as results files and feature names write it ("0.03", "0.1").
inline std::string inlierRadiusName(std::size_t r) {
  std::ostringstream name;
  name << kInlierRadii.at(r);
  return name.str();
}

/// The feature name of the `r`-th inlier share of the pair `pair` names
/// ("icp/tuned:Sedan:within_0.03m").
inline std::string inlierShareFeatureName(const std::string& pair, std::size_t r) {
  return pair + ":within_" + inlierRadiusName(r) + "m";
}

/// Whether `name` is one inlierShareFeatureName gives.
inline bool isInlierShareFeatureName(const std::string& name) {
  return name.find(":within_") != std::string::npos;
}

/// The inlier shares of the aligned points' squared distances to their nearest model points
/// (m^2, as the fitness averages them); zeros for none.
inline InlierShares inlierShares(const std::vector<float>& squared_distances) {
  InlierShares shares{};
  if (squared_distances.empty()) {
    return shares;
  }
  for (std::size_t r = 0; r < kInlierRadii.size(); ++r) {
    const double bound = kInlierRadii[r] * kInlierRadii[r];
    const auto within = std::count_if(squared_distances.begin(), squared_distances.end(),
                                      [&](float squared) { return squared < bound; });
    shares[r] = static_cast<float>(static_cast<double>(within) /
                                   static_cast<double>(squared_distances.size()));
  }
  return shares;
}

}  // namespace granular
