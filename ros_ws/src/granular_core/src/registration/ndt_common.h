// What ndt.cpp (NdtMatcher) and reference.cpp (PCL's NDT) share.
#pragma once

#include "granular_core/registration/registration.h"

namespace granular {
namespace ndt_detail {

// An NDT alignment's state from what PCL's NDT (or NdtMatcher) reports.
inline RegistrationState ndtState(double likelihood, bool converged, int iterations,
                                  int max_iterations) {
  if (likelihood == 0.0) {
    return RegistrationState::kNoCorrespondences;  // no object point near any model cell
  }
  if (!converged) {
    return RegistrationState::kFailed;
  }
  return iterations >= max_iterations ? RegistrationState::kIterations
                                      : RegistrationState::kTransform;
}

}  // namespace ndt_detail
}  // namespace granular
