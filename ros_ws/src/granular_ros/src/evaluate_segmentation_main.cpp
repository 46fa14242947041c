// evaluate_segmentation: the box-free segmentation against ground-truth boxes, over a
// bag-to-files folder (pcd/<stamp>.pcd with detections_3d/<stamp>.json).
#include <iostream>
#include <optional>
#include <string>

#include <granular_core/runs/segmentation_run.h>

#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

namespace {

std::string usage() {
  return "usage: evaluate_segmentation --frames FOLDER [options]\n"
         "\n"
         "Segments every cloud of a bag-to-files folder (pcd/<stamp>.pcd) without looking at\n"
         "its boxes, and compares the segments with the true boxes of detections_3d/\n"
         "<stamp>.json: greedy one-to-one matching of box centres in x-y, nearest first.\n"
         "Prints the recall (true objects of at least --min-points points with a segment\n"
         "centre within --max-distance), the footprint figure (with a segment centre inside\n"
         "their footprint: a box of the visible faces of a car seen from behind has its centre\n"
         "on the rear), the share of segments that match no true object, what each gate\n"
         "removed, and the time per cloud. Needs no roscore.\n"
         "\n"
         "options:\n"
         "  --frames FOLDER        bag-to-files folder\n"
         "  --config FILE          YAML file like config/segmentation.yaml\n"
         "  --ground-config FILE   YAML file like config/ground.yaml\n"
         "  --method NAME          objects (ground, range-aware grid, gates; default) or\n"
         "                         occupancy (the paper's grid on the whole cloud)\n"
         "  --max-distance M       metres between matched centres (default 1)\n"
         "  --min-points N         points a true box must hold to count (default 10)\n"
         "  --field-of-view DEG    count objects and segments within DEG of straight ahead\n"
         "                         only, e.g. 40 for KITTI's camera-labelled frames\n"
         "                         (default 180: all around)\n"
         "  --max-range M          count objects and segments nearer than M metres only\n"
         "  --sensor-height M      the sensor's height above the road (plane.sensor_height\n"
         "                         of --ground-config; the simulator's is 2.3)\n"
         "  --azimuth-step DEG     the sensor's angle between returns along a ring\n"
         "                         (objects.azimuth_step_deg; the simulator's is 1)\n"
         "  --help                 print this help and exit\n"
         "\n"
         "Exit status: 0 done, 1 unreadable input, 2 bad option or configuration.\n"
         "\n"
         "configuration keys (--config) and their defaults:\n" +
         granular_ros::configurationHelp<granular::SegmentationStageConfig>() +
         "\nground configuration keys (--ground-config) and their defaults:\n" +
         granular_ros::configurationHelp<granular::GroundConfig>();
}

}  // namespace

int main(int argc, char** argv) {
  std::string frames;
  std::optional<std::string> config_file;
  std::optional<std::string> ground_config_file;
  std::optional<std::string> method;
  std::optional<double> sensor_height;
  std::optional<double> azimuth_step;
  granular::SegmentationEvaluationOptions options;
  granular::SegmentationStageConfig config;
  granular::GroundConfig ground;
  granular_ros::Tool tool("evaluate_segmentation", usage);
  tool.options()
      .required("--frames", frames)
      .value("--config", config_file)
      .value("--ground-config", ground_config_file)
      .value("--method", method)
      .number("--max-distance", options.max_distance)
      .number("--min-points", options.min_points)
      .number("--field-of-view", options.half_field_of_view_deg)
      .number("--max-range", options.max_range)
      .custom("--sensor-height",
              [&](granular_ros::OptionReader& reader) {
                sensor_height = granular_ros::parseNumber<double>("--sensor-height", reader.value());
              })
      .custom("--azimuth-step", [&](granular_ros::OptionReader& reader) {
        azimuth_step = granular_ros::parseNumber<double>("--azimuth-step", reader.value());
      });
  const auto configure = [&] {
    config = granular_ros::buildConfig<granular::SegmentationStageConfig>(
        config_file, [&](granular::SegmentationStageConfig& stage) {
          if (method) {
            const auto chosen = granular::config::enumFromName<granular::SegmentationMethod>(*method);
            if (!chosen) {
              throw std::invalid_argument("--method: expected objects or occupancy, got '" +
                                          *method + "'");
            }
            stage.method = *chosen;
          }
          if (azimuth_step) {
            stage.objects.azimuth_step_deg = *azimuth_step;
          }
        });
    ground = granular_ros::buildConfig<granular::GroundConfig>(
        ground_config_file, [&](granular::GroundConfig& chosen) {
          if (sensor_height) {
            chosen.plane.sensor_height = *sensor_height;
          }
        });
    if (!(options.max_distance >= 0.0) || !(options.half_field_of_view_deg > 0.0) ||
        !(options.max_range > 0.0)) {
      throw std::invalid_argument(
          "--max-distance must not be negative, --field-of-view and --max-range positive");
    }
  };
  return tool.run(argc, argv, configure, [&] {
    options.progress = tool.progress("segmenting", "clouds");
    granular::evaluateSegmentation(frames, ground, config, options).report(std::cout);
  });
}
