#pragma once

#include <array>
#include <cstddef>
#include <utility>
#include <map>
#include <optional>
#include <string>

#include "granular_core/config/fields.h"

namespace granular {

/// The registration algorithms of the report's section 8 (PCL, point type pcl::PointXYZ).
enum class RegistrationMethod {
  kIcp,    ///< 8.1: pcl::IterativeClosestPoint (SVD)
  kIcpNl,  ///< 8.2: pcl::IterativeClosestPointNonLinear (Levenberg-Marquardt)
  kNdt,    ///< 8.3: pcl::NormalDistributionsTransform
};

template <>
struct config::EnumNames<RegistrationMethod> {
  static constexpr const char* what = "method";
  static constexpr std::array<std::pair<RegistrationMethod, const char*>, 3> values{
      {{RegistrationMethod::kIcp, "icp"},
       {RegistrationMethod::kIcpNl, "icp_nl"},
       {RegistrationMethod::kNdt, "ndt"}}};
};

/// "icp", "icp_nl" or "ndt".
inline const char* registrationMethodName(RegistrationMethod method) {
  return config::enumName(method);
}

/// The method called `name`, or nullopt.
inline std::optional<RegistrationMethod> registrationMethodFromName(const std::string& name) {
  return config::enumFromName<RegistrationMethod>(name);
}

/// ICP and ICP-NL parameters (8.1.1). An alignment converges when DefaultConvergenceCriteria
/// ends it by transformation_epsilon (TRANSFORM) or by the mean squared error of the
/// correspondences no longer changing (ABS_MSE, REL_MSE); PCL checks the iteration limit
/// first, so a run that reaches max_iterations has not converged, whatever its last step
/// (PCL's hasConverged() is true for it all the same).
struct IcpClassifierConfig {
  int max_iterations = 1;
  /// m: source and target points farther apart than this are not paired. Fewer than 3 pairs
  /// (ICP) or 4 pairs (ICP-NL) end the run as "no_correspondences".
  double max_correspondence_distance = 0.01;
  /// m^2: converged when the squared translation of the last step is at most this and its
  /// rotation angle has cos >= 1 - transformation_epsilon.
  double transformation_epsilon = 1e-9;
  /// Converged when the mean squared distance of the pairs changes by less than this fraction
  /// from one iteration to the next (PCL's relative MSE criterion).
  double euclidean_fitness_epsilon = 0.001;
  /// A coarse stage first: up to this many iterations (fewer when its own convergence criteria
  /// end it) pairing points up to coarse_correspondence_distance; the registration above then
  /// starts where it left the object, and its state is the result's. 0: no coarse stage, as
  /// the report ran. A real car is not the simulated class model, so few of its points lie
  /// within a tight bound of the model before alignment; a few iterations with a wider one
  /// bring them there (docs/classification.md measures it on KITTI's cars).
  int coarse_iterations = 0;
  /// m: the coarse stage's pairing bound.
  double coarse_correspondence_distance = 0.1;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("max_iterations", self.max_iterations, config::atLeast(1));
    visit("max_correspondence_distance", self.max_correspondence_distance, config::positive("m"));
    visit("transformation_epsilon", self.transformation_epsilon, config::nonNegative("m^2"));
    visit("euclidean_fitness_epsilon", self.euclidean_fitness_epsilon, config::nonNegative());
    visit("coarse_iterations", self.coarse_iterations, config::atLeast(0));
    visit("coarse_correspondence_distance", self.coarse_correspondence_distance,
          config::positive("m"));
  }
};

/// NDT parameters (8.3). PCL's NDT has no convergence-criteria object; here an alignment
/// converges when it stops before max_iterations because its last step (Newton direction
/// times the More-Thuente step length) moved by at most transformation_epsilon, or because the
/// Newton step was zero, with at least one source point near a target cell. Reaching
/// max_iterations is not convergence (PCL's hasConverged() is true for it), nor is a score of
/// zero: no source point within `resolution` of a cell centre, so nothing was matched.
struct NdtClassifierConfig {
  /// m^2: converged when the squared translation of the last step is at most this.
  double transformation_epsilon = 0.01;
  /// m: the longest step the More-Thuente line search may take.
  double step_size = 0.1;
  int max_iterations = 35;
  /// m: edge of the target's voxels; each voxel with at least min_points_per_voxel model points
  /// becomes one normal distribution (mean and covariance).
  double resolution = 0.1;
  /// Model points a voxel needs to be a cell (PCL's default, 6; at least 3).
  int min_points_per_voxel = 6;
  /// Expected fraction of source points with no cell (PCL's default, 0.55); shapes the score.
  double outlier_ratio = 0.55;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("transformation_epsilon", self.transformation_epsilon, config::nonNegative("m^2"));
    visit("step_size", self.step_size, config::positive("m"));
    visit("max_iterations", self.max_iterations, config::atLeast(1));
    visit("resolution", self.resolution, config::positive("m"));
    visit("min_points_per_voxel", self.min_points_per_voxel, config::atLeast(3, "points"));
    visit("outlier_ratio", self.outlier_ratio, config::fraction());
  }
};

/// Every tunable of the registration classifiers. The defaults here are the report's values
/// (preset "report"); registrationPresets() has the others.
///
/// The fitness of an object against a model is PCL's getFitnessScore(): the mean squared
/// distance (m^2) from each aligned object point to its nearest model point, over all points.
struct RegistrationClassifierConfig {
  IcpClassifierConfig icp;
  IcpClassifierConfig icp_nl;
  NdtClassifierConfig ndt;
  /// m: object points below this height are dropped before registration (the ground returns
  /// near z = 0 of the object frame, which the models, cut at 0.2 m, do not have). Unset keeps
  /// every point, as the report did.
  std::optional<double> source_min_z;
  /// Points an object keeps for registration at most, evenly spread over its points' order
  /// (after source_min_z); 0 keeps every point, as the report did. A registration's cost grows
  /// with the object's points, and a near vehicle's thousands say no more about its shape than
  /// a hundred of them do (docs/classification.md measures it).
  std::size_t source_max_points = 0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("icp", self.icp);
    visit("icp_nl", self.icp_nl);
    visit("ndt", self.ndt);
    visit("source_min_z", self.source_min_z, config::any("m"));
    visit("source_max_points", self.source_max_points, config::any("points"));
  }
};

/// The built-in presets by name:
///  - "report": the report's values (8.1.1 for ICP and ICP-NL, 8.3 for NDT);
///  - "tuned": the values that classified simulated training drives best (models from one
///    60 s drive, seed 11, or five, objects from another, seed 12), with a coarse stage for
///    ICP and ICP-NL that KITTI's real cars need; config/classification.yaml and
///    docs/classification.md say what was tuned and how;
///  - "fast": "tuned" on at most 50 points an object, for the online node's crowded frames.
std::map<std::string, RegistrationClassifierConfig> registrationPresets();

/// config/classification.yaml: the presets by name, the built-in ones to begin with; a preset
/// the file names anew starts from the report's values.
struct RegistrationPresets {
  std::map<std::string, RegistrationClassifierConfig> presets = registrationPresets();

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("presets", self.presets);
  }

  /// The preset called `name`; std::invalid_argument naming the known ones otherwise.
  const RegistrationClassifierConfig& preset(const std::string& name) const;
};

/// Throws std::invalid_argument naming the field for a value out of range: a non-positive
/// iteration limit, distance, resolution or step, a negative epsilon, an outlier ratio outside
/// [0, 1), fewer than 3 points per voxel, a non-finite source_min_z.
inline void validate(const RegistrationClassifierConfig& config) {
  config::validateFields(config);
}

}  // namespace granular
