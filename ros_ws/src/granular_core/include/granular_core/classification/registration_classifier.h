#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "granular_core/classification/registration_config.h"
#include "granular_core/models/model_cloud.h"

namespace granular {

/// How one registration of an object (source) to a class model (target) ended.
enum class RegistrationState {
  kTransform,          ///< converged: the last step was below transformation_epsilon
  kAbsMse,             ///< converged (ICP): the pairs' mean squared error stopped changing
  kRelMse,             ///< converged (ICP): ... changed by less than euclidean_fitness_epsilon
  kIterations,         ///< not converged: stopped by max_iterations
  kNoCorrespondences,  ///< not converged: too few point pairs (ICP) or none near a cell (NDT)
  kFailed,             ///< not converged: PCL gave up (a non-finite NDT step)
  kTooFewPoints,       ///< not run: the object has fewer points than the method needs
};

/// "transform", "abs_mse", "rel_mse", "iterations", "no_correspondences", "failed",
/// "too_few_points".
const char* registrationStateName(RegistrationState state);

/// The state called `name`, or nullopt.
std::optional<RegistrationState> registrationStateFromName(const std::string& name);

/// True for the states that are convergence: kTransform, kAbsMse, kRelMse. (PCL's
/// hasConverged() is also true for kIterations, and for NDT for kNoCorrespondences.)
bool isConverged(RegistrationState state);

/// Points an object needs for `method`: 3 for ICP (an SVD rigid transform needs three point
/// pairs), 4 for ICP-NL (PCL's Levenberg-Marquardt estimator refuses fewer), 3 for NDT (a
/// rigid pose is not determined by fewer; PCL does not check). An object with fewer gets a
/// kTooFewPoints result for every model instead of a registration.
std::size_t minimumSourcePoints(RegistrationMethod method);

/// The registration of one object against one class model.
struct PairResult {
  RegistrationState state = RegistrationState::kTooFewPoints;
  /// m^2: mean squared distance of the aligned object points to their nearest model points
  /// (PCL's getFitnessScore()); infinity when the registration did not run.
  double fitness = std::numeric_limits<double>::infinity();
  int iterations = 0;  ///< iterations run
  /// Maps the object onto the model (homogeneous, object frame to model frame).
  Eigen::Matrix4f transform = Eigen::Matrix4f::Identity();

  bool converged() const { return isConverged(state); }
  /// True when the registration ran (state is not kTooFewPoints).
  bool ran() const { return state != RegistrationState::kTooFewPoints; }
};

/// The report's three criteria (8.1); each value is an index into the per-model results, or
/// nullopt where the criterion gives no prediction.
struct Predictions {
  /// 1: the object converged to exactly one model: that model.
  std::optional<std::size_t> criterion1;
  /// 2: it converged to one or more models: the converged model with the lowest fitness.
  std::optional<std::size_t> criterion2;
  /// 3: the model with the lowest fitness, converged or not (among the finite fitnesses: a
  /// registration that did not run has none).
  std::optional<std::size_t> criterion3;

  /// The prediction of criterion 1, 2 or 3.
  const std::optional<std::size_t>& criterion(int number) const;
};

/// Applies the three criteria to one object's per-model results. Equal fitness goes to the
/// model listed first.
Predictions predict(const std::vector<PairResult>& per_model);

/// A class model: its label and its cloud in the object frame.
struct LabelledModel {
  std::string label;
  ModelCloud cloud;
};

/// How registerObjects runs.
struct RegisterOptions {
  /// Threads; 0 uses OpenMP's default (every core).
  int threads = 0;
  /// Called with (objects done, objects to do), from one thread at a time; may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
};

/// The number of threads registerObjects runs on with `options`.
int registrationThreads(const RegisterOptions& options);

/// Registers objects against every class model with one method.
///
/// The constructor prepares each model once: its kd-tree (used for the ICP correspondences and
/// for every fitness score) and, for NDT, its voxel grid of normal distributions.
/// registerObjects spreads the objects over threads; each thread has its own registration
/// objects, which share those prebuilt structures read-only. The results do not depend on the
/// number of threads, and equal those of registerObjectsPlain.
class RegistrationClassifier {
 public:
  /// Throws std::invalid_argument for an invalid config, no models, an empty model, or a
  /// repeated or empty label.
  RegistrationClassifier(RegistrationMethod method, const RegistrationClassifierConfig& config,
                         std::vector<LabelledModel> models);
  ~RegistrationClassifier();
  RegistrationClassifier(RegistrationClassifier&&) noexcept;
  RegistrationClassifier& operator=(RegistrationClassifier&&) noexcept;

  RegistrationMethod method() const;
  const RegistrationClassifierConfig& config() const;
  /// The model labels, in the order of the per-model results.
  std::vector<std::string> labels() const;
  /// What preparing the models found, e.g. (NDT) a model without a single voxel of
  /// config.ndt.min_points_per_voxel points at config.ndt.resolution: PCL's NDT then aligns
  /// nothing to it, and its pairs are kNoCorrespondences with the fitness of the object as is.
  const std::vector<std::string>& warnings() const;

  /// result[i][m]: object i against model m. Objects are used as given except for
  /// config.source_min_z; see minimumSourcePoints for small objects.
  std::vector<std::vector<PairResult>> registerObjects(const std::vector<ModelCloud>& objects,
                                                       const RegisterOptions& options = {}) const;

  /// The same results the way the report's loop got them: one thread, and for every pair a
  /// fresh PCL registration object given the model as target, which builds the model's
  /// kd-tree (and NDT voxel grid) again each time. The baseline of the benchmark.
  std::vector<std::vector<PairResult>> registerObjectsPlain(
      const std::vector<ModelCloud>& objects,
      const std::function<void(std::size_t, std::size_t)>& progress = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granular
