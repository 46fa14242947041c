#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "granular_core/registration/registration.h"
#include "granular_core/registration/registration_config.h"

namespace granular {

/// How registerObjects runs.
struct RegisterOptions {
  /// Threads; 0 uses OpenMP's default (every core).
  int threads = 0;
  /// Called with (objects done, objects to do), from one thread at a time; may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
  /// Computes an object's fitness only for the models that can still decide its predictions:
  /// the models are scored in the order of a lower bound of their fitness (from each model's
  /// distance field), and a model whose bound exceeds the second lowest fitness so far among
  /// those its criterion compares (the converged ones for a converged model, all for another)
  /// is marked `rejected`, without a fitness. Every prediction of the three criteria, and
  /// the best and second best fitness of criteria 2 and 3, are those of the full scoring;
  /// the rejected models' fitness and inlier shares are missing, which svm_fitness's features
  /// need.
  bool early_rejection = false;
};

/// The number of threads registerObjects runs on with `options`.
int registrationThreads(const RegisterOptions& options);

/// Registers objects against every class model with one method.
///
/// The constructor prepares each model once: its NearestTree (used for the ICP
/// correspondences and for every fitness score) and, for NDT, its cells. registerObjects
/// spreads the objects over threads; each thread has its own registration objects
/// (RegistrationMethodImpl::aligner), which share those prebuilt structures read-only. The
/// results do not depend on the number of threads, and equal those of the report's loop
/// (registerObjectsReference in reference.h).
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

  /// Builds what RegisterOptions::early_rejection reads (each model's distance field, about
  /// 50 ms of one core for seven car-sized models), once; registerObjects calls it when asked
  /// to reject early, so call it beforehand only to keep that out of the first call's time.
  void prepareEarlyRejection() const;

  /// result[i][m]: object i against model m. Objects are used as given except for
  /// config.source_min_z; see minimumSourcePoints for small objects.
  std::vector<std::vector<PairResult>> registerObjects(const std::vector<ModelCloud>& objects,
                                                       const RegisterOptions& options = {}) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granular
