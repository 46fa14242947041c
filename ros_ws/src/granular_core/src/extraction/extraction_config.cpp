#include "granular_core/extraction/extraction_config.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <stdexcept>

namespace granular {

void validate(const ExtractionConfig& config) {
  if (!config.padding.allFinite() || (config.padding.array() < 0.0).any()) {
    throw std::invalid_argument("padding must be finite and not negative");
  }
  if (config.n_thresh.empty()) {
    throw std::invalid_argument("n_thresh must hold at least one threshold");
  }
  if (std::find(config.n_thresh.begin(), config.n_thresh.end(), 0u) != config.n_thresh.end()) {
    throw std::invalid_argument("n_thresh values must be at least 1");
  }
  if (std::find(config.labels.begin(), config.labels.end(), "") != config.labels.end()) {
    throw std::invalid_argument("labels must not contain an empty label");
  }
  if (!std::isfinite(config.max_box_size) || config.max_box_size <= 0.0) {
    throw std::invalid_argument("max_box_size must be positive and finite, got " +
                                std::to_string(config.max_box_size));
  }
}

}  // namespace granular
