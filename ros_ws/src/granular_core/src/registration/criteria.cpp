#include "granular_core/registration/criteria.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace granular {
namespace {

// The lowest-fitness result among those `eligible` accepts; the first of equals.
template <typename Eligible>
std::optional<std::size_t> lowestFitness(const std::vector<PairResult>& per_model,
                                         Eligible eligible) {
  std::optional<std::size_t> best;
  for (std::size_t m = 0; m < per_model.size(); ++m) {
    if (eligible(per_model[m]) && (!best || per_model[m].fitness < per_model[*best].fitness)) {
      best = m;
    }
  }
  return best;
}

}  // namespace

const std::optional<std::size_t>& Predictions::criterion(int number) const {
  switch (number) {
    case 1:
      return criterion1;
    case 2:
      return criterion2;
    case 3:
      return criterion3;
    default:
      throw std::out_of_range("criteria are numbered 1 to 3, not " + std::to_string(number));
  }
}

Predictions predict(const std::vector<PairResult>& per_model) {
  Predictions predictions;
  std::size_t converged = 0;
  for (std::size_t m = 0; m < per_model.size(); ++m) {
    if (per_model[m].converged()) {
      predictions.criterion1 = m;
      ++converged;
    }
  }
  if (converged != 1) {
    predictions.criterion1.reset();
  }
  predictions.criterion2 = lowestFitness(per_model, [](const PairResult& result) {
    return result.converged() && std::isfinite(result.fitness);
  });
  predictions.criterion3 = lowestFitness(
      per_model, [](const PairResult& result) { return std::isfinite(result.fitness); });
  return predictions;
}

}  // namespace granular
