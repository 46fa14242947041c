#pragma once

#include <optional>
#include <string>
#include <vector>

#include <granular_core/runs/fit_cuboids_run.h>

#include "granular_ros/box_free_options.h"
#include "granular_ros/presets.h"
#include "granular_ros/tool.h"

namespace granular_ros {

/// fit_cuboids' command line: its options, each declared once with its help, and the --help
/// text around them.
struct FitCuboidsOptions {
  std::string frames;
  std::string out;
  std::optional<std::string> models;
  std::optional<std::string> method;
  std::optional<std::string> config_file;
  std::optional<std::string> boxes;
  std::optional<std::string> classifier_file;
  std::vector<std::string> prior_classes;
  std::optional<std::string> name_with;
  std::optional<std::string> name_models;
  std::optional<std::string> class_models;
  std::string preset = kDefaultPreset;
  std::optional<std::string> registration_config;
  std::optional<std::string> extraction_config;
  bool track = false;
  std::optional<std::string> tracking_config_file;
  int threads = 0;
  bool overwrite = false;
  BoxFreeOptions box_free;

  /// Describes the tool and binds these fields to its options.
  void declareIn(Tool& tool);
  /// The fitter's configuration: defaults, --config, then --method and --prior-classes.
  granular::CuboidConfig config() const;
  /// The run's ground, segmentation, boxes, tracking and naming padding from the options;
  /// std::invalid_argument
  /// for options that do not go together with each other or with `config`.
  void configure(granular::FitCuboidsOptions& run, const granular::CuboidConfig& config);
};

}  // namespace granular_ros
