#pragma once

#include <optional>
#include <string>
#include <vector>

#include <granular_core/cuboids/cuboid_config.h>
#include <granular_core/runs/segmentation_run.h>

#include "granular_ros/box_free_options.h"
#include "granular_ros/tool.h"

namespace granular_ros {

/// evaluate_segmentation's command line: its options, each declared once with its help, and
/// the --help text around them.
struct EvaluateSegmentationOptions {
  std::string frames;
  BoxFreeOptions box_free;
  std::optional<std::string> method;
  std::optional<std::string> classifier_file;
  std::optional<std::string> cuboids_file;
  std::vector<std::string> prior_classes;
  std::string save;
  bool overwrite = false;
  /// The figures' options (max distance, min points, field of view, range).
  granular::SegmentationEvaluationOptions evaluation;

  /// Describes the tool and binds these fields to its options.
  void declareIn(Tool& tool);
  /// The segmentation's configuration: defaults, --config, the sensor, --method.
  granular::SegmentationStageConfig segmentation() const;
  /// The cuboids of --cuboids (with --prior-classes), when given; std::invalid_argument for
  /// --prior-classes without --cuboids or the model method (it needs class models).
  std::optional<granular::CuboidConfig> cuboids() const;
  /// std::invalid_argument unless the figures' options are in range.
  void checkFigures() const;
};

}  // namespace granular_ros
