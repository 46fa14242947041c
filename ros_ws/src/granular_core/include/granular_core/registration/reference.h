#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "granular_core/registration/registration.h"

namespace granular {

/// The report's loop, as the report ran it: one thread, and for every object-model pair a
/// fresh PCL registration object (IterativeClosestPoint, IterativeClosestPointNonLinear or
/// NormalDistributionsTransform) given the model as target, which builds the model's kd-tree
/// (and NDT voxel grid) again each time, and PCL's own getFitnessScore(). The reference that
/// RegistrationClassifier must equal bit for bit, and the baseline of bench_registration; for
/// tests and benchmarks only (library granular_registration_reference).
std::vector<std::vector<PairResult>> registerObjectsReference(
    RegistrationMethod method, const RegistrationClassifierConfig& config,
    const std::vector<LabelledModel>& models, const std::vector<ModelCloud>& objects,
    const std::function<void(std::size_t, std::size_t)>& progress = {});

/// How a run's results (`ours`) differ from the reference's on the same objects and models,
/// each indexed [object][model].
struct ReferenceComparison {
  /// Objects whose prediction differs under any of the three criteria.
  std::size_t different_predictions = 0;
  /// Pairs whose state, iterations, fitness (unless ours was rejected early; NaN equals NaN)
  /// or transform differ.
  std::size_t different_pairs = 0;
  /// Pairs of ours whose fitness was rejected early (RegisterOptions::early_rejection).
  std::size_t rejected_pairs = 0;
};

ReferenceComparison compareWithReference(const std::vector<std::vector<PairResult>>& reference,
                                         const std::vector<std::vector<PairResult>>& ours);

/// Share of the objects whose criterion-2 prediction is their label (`labels`, one per object;
/// no prediction counts as wrong); 0 without objects.
double criterion2Accuracy(const std::vector<std::vector<PairResult>>& results,
                          const std::vector<std::string>& labels,
                          const std::vector<LabelledModel>& models);

}  // namespace granular
