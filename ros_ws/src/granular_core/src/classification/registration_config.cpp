#include "granular_core/classification/registration_config.h"

#include <cmath>
#include <stdexcept>

namespace granular {
namespace {

void require(bool condition, const std::string& what) {
  if (!condition) {
    throw std::invalid_argument(what);
  }
}

void requirePositive(double value, const std::string& field) {
  require(std::isfinite(value) && value > 0.0, field + " must be a positive number");
}

void requireNonNegative(double value, const std::string& field) {
  require(std::isfinite(value) && value >= 0.0, field + " must be a number >= 0");
}

void validateIcp(const IcpClassifierConfig& icp, const std::string& prefix) {
  require(icp.max_iterations >= 1, prefix + "max_iterations must be at least 1");
  requirePositive(icp.max_correspondence_distance, prefix + "max_correspondence_distance");
  requireNonNegative(icp.transformation_epsilon, prefix + "transformation_epsilon");
  requireNonNegative(icp.euclidean_fitness_epsilon, prefix + "euclidean_fitness_epsilon");
}

}  // namespace

const char* registrationMethodName(RegistrationMethod method) {
  switch (method) {
    case RegistrationMethod::kIcp:
      return "icp";
    case RegistrationMethod::kIcpNl:
      return "icp_nl";
    case RegistrationMethod::kNdt:
      return "ndt";
  }
  return "unknown";
}

std::optional<RegistrationMethod> registrationMethodFromName(const std::string& name) {
  for (const RegistrationMethod method :
       {RegistrationMethod::kIcp, RegistrationMethod::kIcpNl, RegistrationMethod::kNdt}) {
    if (name == registrationMethodName(method)) {
      return method;
    }
  }
  return std::nullopt;
}

std::map<std::string, RegistrationClassifierConfig> registrationPresets() {
  // Chosen on training drives only (scripts/tune_registration); config/classification.yaml and
  // docs/classification.md record the search.
  RegistrationClassifierConfig tuned;
  tuned.icp.max_iterations = 100;
  tuned.icp.max_correspondence_distance = 0.05;
  tuned.icp_nl.max_iterations = 30;
  tuned.icp_nl.max_correspondence_distance = 0.1;
  tuned.ndt.resolution = 0.3;
  tuned.ndt.min_points_per_voxel = 3;
  tuned.source_min_z = 0.2;
  return {{"report", RegistrationClassifierConfig()}, {"tuned", tuned}};
}

void validate(const RegistrationClassifierConfig& config) {
  validateIcp(config.icp, "icp.");
  validateIcp(config.icp_nl, "icp_nl.");
  const NdtClassifierConfig& ndt = config.ndt;
  requireNonNegative(ndt.transformation_epsilon, "ndt.transformation_epsilon");
  requirePositive(ndt.step_size, "ndt.step_size");
  require(ndt.max_iterations >= 1, "ndt.max_iterations must be at least 1");
  requirePositive(ndt.resolution, "ndt.resolution");
  require(ndt.min_points_per_voxel >= 3, "ndt.min_points_per_voxel must be at least 3");
  require(std::isfinite(ndt.outlier_ratio) && ndt.outlier_ratio >= 0.0 &&
              ndt.outlier_ratio < 1.0,
          "ndt.outlier_ratio must be in [0, 1)");
  require(!config.source_min_z || std::isfinite(*config.source_min_z),
          "source_min_z must be a finite number or unset");
}

bool operator==(const IcpClassifierConfig& a, const IcpClassifierConfig& b) {
  return a.max_iterations == b.max_iterations &&
         a.max_correspondence_distance == b.max_correspondence_distance &&
         a.transformation_epsilon == b.transformation_epsilon &&
         a.euclidean_fitness_epsilon == b.euclidean_fitness_epsilon;
}

bool operator==(const NdtClassifierConfig& a, const NdtClassifierConfig& b) {
  return a.transformation_epsilon == b.transformation_epsilon && a.step_size == b.step_size &&
         a.max_iterations == b.max_iterations && a.resolution == b.resolution &&
         a.min_points_per_voxel == b.min_points_per_voxel && a.outlier_ratio == b.outlier_ratio;
}

bool operator==(const RegistrationClassifierConfig& a, const RegistrationClassifierConfig& b) {
  return a.icp == b.icp && a.icp_nl == b.icp_nl && a.ndt == b.ndt &&
         a.source_min_z == b.source_min_z;
}

}  // namespace granular
