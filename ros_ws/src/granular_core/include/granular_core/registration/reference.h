#pragma once

#include <cstddef>
#include <functional>
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

}  // namespace granular
