#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "granular_core/dataset/models_folder.h"
#include "granular_core/point_types.h"
#include "granular_core/search/inlier_shares.h"
#include "granular_core/registration/registration_config.h"
#include "granular_core/search/nearest_tree.h"

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

/// The parameters `method` registers with under `config` (its own config section, the source's
/// minimum height and minimumSourcePoints), keys sorted, as classify_registration's results
/// record them and svm_fitness compares them.
nlohmann::json registrationParameters(RegistrationMethod method,
                                      const RegistrationClassifierConfig& config);

/// The object as registered under `config`: its points at or above source_min_z when set (all
/// of them otherwise), then at most source_max_points of those, evenly spread over their order
/// when there are more.
ModelCloud::ConstPtr registrationSource(const ModelCloud& object,
                                        const RegistrationClassifierConfig& config);
/// registrationSource(object, config)->size(), counted without the copy.
std::size_t registrationSourceSize(const ModelCloud& object,
                                   const RegistrationClassifierConfig& config);

/// The registration of one object against one class model.
struct PairResult {
  RegistrationState state = RegistrationState::kTooFewPoints;
  /// m^2: mean squared distance of the aligned object points to their nearest model points
  /// (PCL's getFitnessScore()); infinity when the registration did not run, or when the
  /// fitness was rejected early.
  double fitness = std::numeric_limits<double>::infinity();
  /// The fitness was not computed: a lower bound of it showed that this model could be
  /// neither the best nor the second best of the object under criterion 2 or 3
  /// (RegisterOptions::early_rejection).
  bool rejected = false;
  /// Scored with the fitness (inlier_shares.h); zeros where the fitness is not.
  InlierShares inlier_shares{};
  int iterations = 0;  ///< iterations run
  /// Maps the object onto the model (homogeneous, object frame to model frame).
  Eigen::Matrix4f transform = Eigen::Matrix4f::Identity();

  bool converged() const { return isConverged(state); }
  /// True when the registration ran (state is not kTooFewPoints).
  bool ran() const { return state != RegistrationState::kTooFewPoints; }
  /// The fitness when the registration ran and gave a finite one, else none: what the results
  /// files record, and what svm_fitness's features are built from offline and online alike.
  std::optional<double> reportedFitness() const {
    return ran() && std::isfinite(fitness) ? std::optional<double>(fitness) : std::nullopt;
  }
};

/// A pair whose registration threw: PCL gave up.
PairResult failedPair();

/// The class models as every method sees them: each cloud, and its NearestTree (built once,
/// shared read-only by every thread) for the correspondences and the fitness; for ICP and
/// ICP-NL bounded by their maximum correspondence distance. With a coarse stage (ICP and ICP-NL's
/// coarse_iterations), a second tree per model bounded by its coarse_correspondence_distance.
struct PreparedModels {
  std::vector<ModelCloud::ConstPtr> clouds;
  std::vector<NearestTree::Ptr> trees;
  std::vector<NearestTree::Ptr> coarse_trees;  ///< empty without a coarse stage
};

/// One thread's registration objects for every model of a method.
class ModelAligner {
 public:
  virtual ~ModelAligner() = default;
  /// Registers `source` (at least minimumSourcePoints points) to model `model`: everything but
  /// the fitness, which the caller scores with the model's NearestTree.
  virtual PairResult align(const ModelCloud::ConstPtr& source, std::size_t model) = 0;
};

/// A registration method prepared against the class models: what it builds once per model
/// (read-only afterwards), and an aligner per thread.
class RegistrationMethodImpl {
 public:
  virtual ~RegistrationMethodImpl() = default;
  virtual std::unique_ptr<ModelAligner> aligner() const = 0;
  /// What preparing the models found (e.g. an NDT model without cells).
  virtual std::vector<std::string> warnings() const { return {}; }
};

/// The three methods (icp.cpp, icp_nl.cpp, ndt.cpp); `models` outlives what they return.
std::unique_ptr<RegistrationMethodImpl> prepareIcp(const IcpClassifierConfig& config,
                                                   const PreparedModels& models);
std::unique_ptr<RegistrationMethodImpl> prepareIcpNl(const IcpClassifierConfig& config,
                                                     const PreparedModels& models);
std::unique_ptr<RegistrationMethodImpl> prepareNdt(const NdtClassifierConfig& config,
                                                   const PreparedModels& models,
                                                   const std::vector<std::string>& labels);

}  // namespace granular
