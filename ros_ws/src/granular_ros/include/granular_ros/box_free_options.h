#pragma once

#include <optional>
#include <string>

#include <granular_core/ground/ground.h>
#include <granular_core/segmentation/object_segmentation.h>
#include <granular_core/supervised/supervised_classifier.h>

#include "granular_ros/command_line.h"

namespace granular_ros {

/// The box-free path's settings as the tools take them: the ground's and the segmentation's
/// config files (config/ground.yaml, config/segmentation.yaml) and the sensor's mounting height
/// and angle between returns, which differ from one sensor to the next.
struct BoxFreeOptions {
  std::optional<std::string> ground_config;
  std::optional<std::string> segmentation_config;
  std::optional<double> sensor_height;  ///< m, over the ground config's plane.sensor_height
  std::optional<double> azimuth_step;   ///< deg, over the segmentation's objects.azimuth_step_deg

  /// Adds --ground-config, `segmentation_option` (a file like config/segmentation.yaml),
  /// --sensor-height and --azimuth-step to `table`.
  void addTo(OptionTable& table, const std::string& segmentation_option = "--segmentation-config");

  /// Whether any of them was given.
  bool given() const {
    return ground_config || segmentation_config || sensor_height || azimuth_step;
  }

  /// The ground stage's configuration: defaults, the file, then --sensor-height; validated.
  granular::GroundConfig ground() const;
  /// The segmentation's: defaults, the file, then --azimuth-step; validated.
  granular::SegmentationStageConfig segmentation() const;

  /// The --help lines of the options addTo adds.
  static std::string help(const std::string& segmentation_option = "--segmentation-config");
};

/// The Background decision's classifier from `file` (train_classifier's); a
/// std::runtime_error naming the file when it knows no class `background_label`.
granular::SupervisedClassifier loadBackgroundClassifier(const std::string& file,
                                                        const std::string& background_label);

}  // namespace granular_ros
