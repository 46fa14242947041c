#include "granular_ros/box_free_options.h"

#include <algorithm>

#include <granular_core/text.h>

#include "granular_ros/config_file.h"

namespace granular_ros {

void BoxFreeOptions::addTo(OptionTable& table, const std::string& segmentation_option) {
  table.value("--ground-config", ground_config)
      .value(segmentation_option, segmentation_config)
      .custom("--sensor-height",
              [this](OptionReader& reader) {
                sensor_height = parseNumber<double>("--sensor-height", reader.value());
              })
      .custom("--azimuth-step", [this](OptionReader& reader) {
        azimuth_step = parseNumber<double>("--azimuth-step", reader.value());
      });
}

granular::GroundConfig BoxFreeOptions::ground() const {
  return buildConfig<granular::GroundConfig>(ground_config, [&](granular::GroundConfig& config) {
    if (sensor_height) {
      config.plane.sensor_height = *sensor_height;
    }
  });
}

granular::SegmentationStageConfig BoxFreeOptions::segmentation() const {
  return buildConfig<granular::SegmentationStageConfig>(
      segmentation_config, [&](granular::SegmentationStageConfig& config) {
        if (azimuth_step) {
          config.objects.azimuth_step_deg = *azimuth_step;
        }
      });
}

std::string BoxFreeOptions::help(const std::string& segmentation_option) {
  // The option and its argument in the first 25 columns, as the tools' other options.
  std::string segmentation = "  " + segmentation_option + " FILE";
  segmentation += segmentation.size() < 24 ? std::string(25 - segmentation.size(), ' ')
                                           : "\n" + std::string(25, ' ');
  return "  --ground-config FILE   YAML file like config/ground.yaml\n" + segmentation +
         "YAML file like config/segmentation.yaml\n"
         "  --sensor-height M      the sensor's height above the road (plane.sensor_height of\n"
         "                         --ground-config; KITTI's HDL-64E 1.73, the simulator's 2.3)\n"
         "  --azimuth-step DEG     the sensor's angle between returns along a ring\n"
         "                         (objects.azimuth_step_deg; HDL-64E 0.176, the simulator 1)\n";
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
