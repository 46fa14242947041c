// evaluate_segmentation: the box-free segmentation against ground-truth boxes, over a
// bag-to-files folder (pcd/<stamp>.pcd with detections_3d/<stamp>.json).
#include <algorithm>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <granular_core/runs/segmentation_run.h>
#include <granular_core/text.h>

#include "granular_ros/box_free_options.h"
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
         "  --frames FOLDER        bag-to-files folder\n" +
         granular_ros::BoxFreeOptions::help("--config") +
         "  --method NAME          objects (ground, range-aware grid, gates; default) or\n"
         "                         occupancy (the paper's grid on the whole cloud)\n"
         "  --classifier FILE      the Background decision: a train_classifier file trained\n"
         "                         with Background objects (extract_objects --background);\n"
         "                         the segments it calls Background with a score of at\n"
         "                         least background.min_score (1: unanimous) are dropped,\n"
         "                         except those beyond background.abstain_range with fewer\n"
         "                         than abstain_points points, and the figures are printed\n"
         "                         again for the rest\n"
         "  --cuboids FILE         score full-vehicle cuboids instead of the segments' boxes:\n"
         "                         a YAML file like config/cuboids.yaml (geometric or\n"
         "                         rectangle method), fitted to each segment as fit_cuboids\n"
         "                         --boxes segment does; the time includes the fitting\n"
         "  --prior-classes LIST   with --cuboids: the size priors to choose among, comma-\n"
         "                         separated (KITTI: Car,Van,Truck; the simulator:\n"
         "                         Sedan,SUV,Hatchback,Jeep,BoxTruck,SchoolBus)\n"
         "  --save FOLDER          also write what the segmentation saw, per frame:\n"
         "                         <stamp>.json, the segments (or cuboids) as detections\n"
         "                         (label unknown, or --classifier's), and <stamp>.pcd,\n"
         "                         x y z with each point's height above the ground and\n"
         "                         its segment (-1 ground, 0 none, k+1 segment k), for\n"
         "                         render_frame\n"
         "  --allow-other-frames   go on when a cloud's road is not where the sensor's frame\n"
         "                         puts it (ground sensor_frame: a world or vehicle frame),\n"
         "                         naming each such frame among those without ground;\n"
         "                         without it the first such frame stops the run (exit 1)\n"
         "  --overwrite            replace a --save folder a granular tool wrote\n"
         "  --max-distance M       metres between matched centres (default 1)\n"
         "  --min-points N         points a true box must hold to count (default 10)\n"
         "  --field-of-view DEG    count objects and segments within DEG of straight ahead\n"
         "                         only, e.g. 40 for KITTI's camera-labelled frames\n"
         "                         (default 180: all around)\n"
         "  --max-range M          count objects and segments nearer than M metres only\n"
         "  -h, --help             print this help and exit\n"
         "\n"
         "Exit status: 0 done, 1 failed (unreadable input, a cloud not in the sensor's frame,\n"
         "a classifier without the Background class, --save folder not writable or holding\n"
         "results without --overwrite), 2 bad option or configuration, 130/143/129\n"
         "interrupted by SIGINT/SIGTERM/SIGHUP.\n"
         "\n"
         "configuration keys (--config) and their defaults:\n" +
         granular_ros::configurationHelp<granular::SegmentationStageConfig>() +
         "\nground configuration keys (--ground-config) and their defaults:\n" +
         granular_ros::configurationHelp<granular::GroundConfig>();
}

}  // namespace

int main(int argc, char** argv) {
  std::string frames;
  granular_ros::BoxFreeOptions box_free;
  std::optional<std::string> method;
  std::optional<std::string> classifier_file;
  std::string save;
  bool overwrite = false;
  std::optional<granular::SupervisedClassifier> classifier;
  std::optional<std::string> cuboids_file;
  std::optional<std::string> prior_classes;
  granular::CuboidConfig cuboids;
  std::unique_ptr<granular::CuboidFitter> fitter;
  granular::SegmentationEvaluationOptions options;
  granular::SegmentationStageConfig config;
  granular::GroundConfig ground;
  granular_ros::Tool tool("evaluate_segmentation", usage);
  tool.options()
      .required("--frames", frames)
      .value("--method", method)
      .value("--classifier", classifier_file)
      .value("--cuboids", cuboids_file)
      .value("--prior-classes", prior_classes)
      .value("--save", save)
      .flag("--overwrite", overwrite)
      .flag("--allow-other-frames", options.allow_other_frames)
      .number("--max-distance", options.max_distance)
      .number("--min-points", options.min_points)
      .number("--field-of-view", options.half_field_of_view_deg)
      .number("--max-range", options.max_range);
  box_free.addTo(tool.options(), "--config");
  const auto configure = [&] {
    box_free.frames = frames;  // whose clouds --sensor auto measures
    config = box_free.segmentation();
    ground = box_free.ground();
    if (method) {
      config.method =
          granular_ros::parseChoice<granular::SegmentationMethod>("--method", *method);
    }
    if (prior_classes && !cuboids_file) {
      throw std::invalid_argument("--prior-classes chooses the cuboids' priors: it needs --cuboids");
    }
    if (cuboids_file) {
      cuboids = granular_ros::buildConfig<granular::CuboidConfig>(
          cuboids_file, [&](granular::CuboidConfig& loaded) {
            if (prior_classes) {
              loaded.geometric.classes = granular_ros::splitList("--prior-classes", *prior_classes);
            }
          });
      if (cuboids.method == granular::CuboidMethod::kModel) {
        throw std::invalid_argument(
            "--cuboids: the model method needs class models; use method geometric or rectangle");
      }
    }
    if (!(options.max_distance >= 0.0) || !(options.half_field_of_view_deg > 0.0) ||
        !(options.max_range > 0.0)) {
      throw std::invalid_argument(
          "--max-distance must not be negative, --field-of-view and --max-range positive");
    }
  };
  return tool.run(argc, argv, configure, [&] {
    if (classifier_file) {
      classifier.emplace(
          granular_ros::loadBackgroundClassifier(*classifier_file, config.background.label));
      options.classifier = &*classifier;
    }
    if (cuboids_file) {
      fitter = granular::makeCuboidFitter(cuboids, {});
      options.cuboids = fitter.get();
      options.free_space = cuboids.free_space;
    }
    options.save = save;
    options.save_policy = granular_ros::Tool::outputPolicy(overwrite);
    options.progress = tool.progress("segmenting", "clouds");
    granular::evaluateSegmentation(frames, ground, config, options).report(std::cout);
  });
}
