#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "granular_core/registration/registration.h"

namespace granular {

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

}  // namespace granular
