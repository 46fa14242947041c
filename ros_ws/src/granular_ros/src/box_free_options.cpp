#include "granular_ros/box_free_options.h"

#include <algorithm>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <granular_core/dataset/pcd_io.h>
#include <granular_core/text.h>
#include <ros/package.h>

#include "granular_ros/config_file.h"

namespace granular_ros {

void BoxFreeOptions::addTo(OptionTable& table, const std::string& segmentation_option) {
  table.value("--ground-config", ground_config, "FILE", "YAML file like config/ground.yaml")
      .value(segmentation_option, segmentation_config, "FILE",
             "YAML file like config/segmentation.yaml")
      .value("--sensor", sensor, "NAME|FILE|auto",
             "the sensor: config/sensors/NAME.yaml (simulator, hdl64e, os1_64, vlp16, "
             "pandar64), a sensor file, or auto: its height and azimuth step measured from the "
             "frames' clouds")
      .number("--sensor-height", sensor_height, "M",
              "the sensor's height above the road (plane.sensor_height of --ground-config; "
              "KITTI's HDL-64E 1.73, the simulator's 2.3)")
      .number("--azimuth-step", azimuth_step, "DEG",
              "the sensor's angle between returns along a ring (objects.azimuth_step_deg; "
              "HDL-64E 0.176, the simulator 1)");
}

std::filesystem::path sensorsDirectory() {
  // This package's folder: the source (its config/sensors links to the repository's) in a
  // devel space, share/granular_ros in an install space.
  const std::string package = ros::package::getPath("granular_ros");
  if (package.empty()) {
    throw std::invalid_argument(
        "--sensor NAME: package granular_ros not found on ROS_PACKAGE_PATH (source the "
        "workspace's setup.bash), or give the sensor FILE.yaml");
  }
  return std::filesystem::path(package) / "config" / "sensors";
}

namespace {

// The shipped sensors' names for an error message, or why there are none.
std::string shippedSensorNames() {
  std::filesystem::path sensors;
  try {
    sensors = sensorsDirectory();
  } catch (const std::invalid_argument&) {
    return "none known: granular_ros not found on ROS_PACKAGE_PATH";
  }
  std::vector<std::string> names;
  std::error_code unreadable;  // no sensors folder (an install without it): no names
  for (const auto& entry : std::filesystem::directory_iterator(sensors, unreadable)) {
    if (entry.path().extension() == ".yaml") {
      names.push_back(entry.path().stem().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names.empty() ? "none in " + sensors.string() : granular::joined(names);
}

}  // namespace

granular::SensorConfig loadSensorFile(const std::string& name_or_file) {
  const bool is_name = name_or_file.find('/') == std::string::npos &&
                       std::filesystem::path(name_or_file).extension() != ".yaml";
  const std::filesystem::path file = is_name
                                         ? sensorsDirectory() / (name_or_file + ".yaml")
                                         : std::filesystem::path(name_or_file);
  if (!std::filesystem::is_regular_file(file)) {
    throw std::invalid_argument("--sensor " + name_or_file + ": no sensor file " +
                                file.string() + " (sensors: " + shippedSensorNames() +
                                ", auto, or a FILE.yaml)");
  }
  granular::SensorConfig sensor;
  loadConfigFile(file, sensor);
  try {
    granular::validate(sensor);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(file.string() + ": " + error.what());
  }
  return sensor;
}

std::pair<double, double> BoxFreeOptions::sensorValues() const {
  if (sensor_values_) {
    return *sensor_values_;
  }
  if (*sensor != "auto") {
    const granular::SensorConfig file = loadSensorFile(*sensor);
    sensor_values_.emplace(file.mount_height, file.azimuth_step_deg);
    return *sensor_values_;
  }
  // Up to ten clouds spread over the folder.
  std::vector<std::filesystem::path> clouds;
  const std::filesystem::path pcd = frames / "pcd";
  if (std::filesystem::is_directory(pcd)) {
    for (const auto& entry : std::filesystem::directory_iterator(pcd)) {
      if (entry.path().extension() == ".pcd") {
        clouds.push_back(entry.path());
      }
    }
  }
  if (clouds.empty()) {
    throw std::invalid_argument("--sensor auto: no clouds to measure in " + pcd.string());
  }
  std::sort(clouds.begin(), clouds.end());
  const std::size_t taken = std::min<std::size_t>(10, clouds.size());
  std::vector<granular::Cloud> read;
  for (std::size_t i = 0; i < taken; ++i) {
    read.push_back(granular::readPcd(clouds[i * clouds.size() / taken]));
  }
  granular::GroundConfig ground_stage = buildConfig<granular::GroundConfig>(ground_config, {});
  const granular::SensorEstimate estimate = granular::estimateSensor(read, ground_stage);
  if (!estimate.mount_height || !estimate.azimuth_step_deg) {
    throw std::invalid_argument(
        "--sensor auto cannot tell from " + std::to_string(taken) + " clouds of " +
        frames.string() + ": " + granular::joined(estimate.problems, "; ") +
        "; name the sensor (--sensor NAME) or give --sensor-height and --azimuth-step");
  }
  char line[200];
  std::snprintf(line, sizeof(line),
                "sensor auto: mount height %.2f m (the road plane under %zu clouds), azimuth "
                "step %.3f deg (returns along rings)",
                *estimate.mount_height, taken, *estimate.azimuth_step_deg);
  std::cerr << line << std::endl;
  sensor_values_.emplace(*estimate.mount_height, *estimate.azimuth_step_deg);
  return *sensor_values_;
}

granular::GroundConfig BoxFreeOptions::ground() const {
  return buildConfig<granular::GroundConfig>(ground_config, [&](granular::GroundConfig& config) {
    if (sensor) {
      config.plane.sensor_height = sensorValues().first;
    }
    if (sensor_height) {
      config.plane.sensor_height = *sensor_height;
    }
  });
}

granular::SegmentationStageConfig BoxFreeOptions::segmentation() const {
  return buildConfig<granular::SegmentationStageConfig>(
      segmentation_config, [&](granular::SegmentationStageConfig& config) {
        if (sensor) {
          config.objects.azimuth_step_deg = sensorValues().second;
        }
        if (azimuth_step) {
          config.objects.azimuth_step_deg = *azimuth_step;
        }
      });
}

bool isVehicleDecision(const std::string& file) {
  std::ifstream stream(file);
  std::string first_line;
  // An unreadable file is left to the classifier's loader, which names the problem.
  return std::getline(stream, first_line) && first_line.rfind("%YAML:", 0) != 0;
}

granular::SupervisedClassifier loadBackgroundClassifier(const std::string& file,
                                                        const std::string& background_label) {
  granular::SupervisedClassifier classifier = granular::SupervisedClassifier::load(file);
  const std::vector<std::string>& labels = classifier.labels();
  if (std::find(labels.begin(), labels.end(), background_label) == labels.end()) {
    throw std::runtime_error(file + ": the classifier knows no class '" + background_label +
                             "' (it knows " + granular::joined(labels) +
                             "); train it on objects extracted with --background");
  }
  return classifier;
}

}  // namespace granular_ros
