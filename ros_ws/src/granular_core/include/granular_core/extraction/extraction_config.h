#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "granular_core/config/fields.h"

namespace granular {

/// Tunables of the extract stage. The defaults here are the reference values; tools overlay a
/// YAML file and command-line options on them.
struct ExtractionConfig {
  /// Metres added on each side of a box along its own x, y and z axes before cropping. Zero by
  /// default: simulator ground-truth boxes already enclose the whole model, z padding would add
  /// ground returns and x/y padding the neighbours in a queue or a row of parked cars.
  Eigen::Vector3d padding = Eigen::Vector3d::Zero();
  /// N_thresh values, points: an object with fewer points is not written for that threshold.
  std::vector<std::size_t> n_thresh = {10};
  /// Labels to extract; empty extracts every label.
  std::vector<std::string> labels;
  /// m; a box longer, wider or higher than this is skipped as implausible (a 1e30 m box from a
  /// broken detector would turn whole clouds into one object of its class).
  double max_box_size = 30.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("padding", self.padding, config::nonNegative("m"));
    visit("n_thresh", self.n_thresh, config::nonEmpty(config::atLeast(1, "points")));
    visit("labels", self.labels, config::text("a label"));
    visit("max_box_size", self.max_box_size, config::positive("m"));
  }
};

/// Throws std::invalid_argument naming the field when padding is negative or not finite,
/// n_thresh is empty or holds a zero, a label is empty, or max_box_size is not positive and
/// finite.
inline void validate(const ExtractionConfig& config) { config::validateFields(config); }

}  // namespace granular
