#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <granular_core/ground/ground.h>
#include <granular_core/ground/sensor.h>
#include <granular_core/segmentation/object_segmentation.h>
#include <granular_core/supervised/supervised_classifier.h>

#include "granular_ros/command_line.h"

namespace granular_ros {

/// The box-free path's settings as the tools take them: the ground's and the segmentation's
/// config files (config/ground.yaml, config/segmentation.yaml) and the sensor's mounting height
/// and angle between returns, which differ from one sensor to the next: a sensor file
/// (config/sensors/NAME.yaml, or a path), `auto` (measured from the clouds of `frames`), and
/// the two values one by one over either.
struct BoxFreeOptions {
  std::optional<std::string> ground_config;
  std::optional<std::string> segmentation_config;
  std::optional<std::string> sensor;    ///< NAME, FILE.yaml or auto
  std::optional<double> sensor_height;  ///< m, over the sensor's and the ground config's
  std::optional<double> azimuth_step;   ///< deg, over the sensor's and the segmentation's
  /// The bag-to-files folder whose clouds `--sensor auto` measures.
  std::filesystem::path frames;

  /// Adds --ground-config, `segmentation_option` (a file like config/segmentation.yaml),
  /// --sensor, --sensor-height and --azimuth-step, with their help, to `table`.
  void addTo(OptionTable& table, const std::string& segmentation_option = "--segmentation-config");

  /// Whether any of them was given.
  bool given() const {
    return ground_config || segmentation_config || sensor || sensor_height || azimuth_step;
  }

  /// The ground stage's configuration: defaults, the file, the sensor's height, then
  /// --sensor-height; validated.
  granular::GroundConfig ground() const;
  /// The segmentation's: defaults, the file, the sensor's azimuth step, then --azimuth-step;
  /// validated.
  granular::SegmentationStageConfig segmentation() const;

 private:
  /// The sensor's height and azimuth step: its file's, or measured (auto, once, said on
  /// stderr); throws std::invalid_argument for a bad file or clouds that cannot tell.
  std::pair<double, double> sensorValues() const;
  mutable std::optional<std::pair<double, double>> sensor_values_;
};

/// The shipped sensor files: config/sensors of this package's folder as ROS finds it (the
/// source in a devel space, share/granular_ros once installed); std::invalid_argument when
/// ROS does not know the package (no workspace sourced).
std::filesystem::path sensorsDirectory();

/// A sensor file: NAME (sensorsDirectory()/NAME.yaml) or a path; strict and validated, a
/// std::invalid_argument naming the file otherwise.
granular::SensorConfig loadSensorFile(const std::string& name_or_file);

/// Whether `file`, given as a Background decision, is a vehicle decision (the `evidence:` keys
/// of config/cuboids.yaml that train_vehicle_decision tuned on labelled frames) rather than a
/// train_classifier file (OpenCV's YAML, whose first line is "%YAML:1.0").
bool isVehicleDecision(const std::string& file);

/// The Background decision's classifier from `file` (train_classifier's); a
/// std::runtime_error naming the file when it knows no class `background_label`.
granular::SupervisedClassifier loadBackgroundClassifier(const std::string& file,
                                                        const std::string& background_label);

}  // namespace granular_ros
