// fit_cuboids: the command-line face of granular::fitCuboidsFolder. Fits a cuboid to every
// segment (or given box) of every frame of a bag-to-files folder and writes them in the layout
// of its detections_3d/.
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>

#include <granular_core/dataset/models_folder.h>
#include <granular_core/runs/fit_cuboids_run.h>
#include <granular_core/tracking/tracking_config.h>
#include <pcl/console/print.h>

#include "granular_ros/box_free_options.h"
#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

namespace {

std::string usage() {
  return "usage: fit_cuboids --frames FOLDER --out FOLDER [options]\n"
         "\n"
         "Fits a cuboid (label, score, centre, orientation, size) to every object of every\n"
         "frame of a bag-to-files folder (pcd/<stamp>.pcd, detections_3d/<stamp>.json) and\n"
         "writes OUT/<stamp>.json per frame in the layout of detections_3d/, in the sensor\n"
         "frame, so that evaluate_cuboids, extraction and rviz take the cuboids as given\n"
         "boxes. The objects are the box-free segmentation's segments (--boxes segment; the\n"
         "frame's own boxes are never read), or the points in each given box grown by\n"
         "detections.margin on every side (--boxes detections; its heading is not used). The\n"
         "ground under them is the road plane of the ground stage. Methods: geometric (the\n"
         "L-shape of the points seen from above, grown to a class's size prior away from the\n"
         "sensor; label 'unknown', score 1), model (class models registered to the points from\n"
         "the L-shape's headings; label and score of the best model; needs --models) and\n"
         "rectangle (the points' minimum-area rectangle, as segment boxes are: the baseline).\n"
         "Segments without --classifier are cut apart where parked cars touch (split:) and\n"
         "get a cuboid only when the zero-shot vehicle decision (evidence:) calls them a\n"
         "vehicle; the others are counted by verdict in the summary. docs/cuboids.md\n"
         "describes them and what they measured. Needs no roscore.\n"
         "\n"
         "options:\n"
         "  --frames FOLDER        bag-to-files folder\n"
         "  --out FOLDER           folder of <stamp>.json to create\n"
         "  --models FOLDER        class models (<Class>.pcd, as build_models writes them)\n"
         "  --method NAME          geometric, model or rectangle (default: the config's method)\n"
         "  --config FILE          YAML file like config/cuboids.yaml\n"
         "  --boxes WHAT           segment (default; the zero-shot vehicle decision keeps the\n"
         "                         vehicles, or --classifier decides) or detections\n"
         "  --classifier FILE      --boxes segment: the Background decision, a train_classifier\n"
         "                         file trained with Background objects (extract_objects\n"
         "                         --background); the segments it calls Background with a\n"
         "                         score of at least background.min_score (1: unanimous)\n"
         "                         get no cuboid; far sparse segments are kept (see\n"
         "                         background.abstain_points and abstain_range); the\n"
         "                         others' cuboids take its class and score as label\n"
         "                         (where the method gives none: geometric, rectangle),\n"
         "                         unknown where its answer was a Background not sure\n"
         "                         enough to drop; or a vehicle decision that\n"
         "                         train_vehicle_decision tuned on labelled frames (the\n"
         "                         evidence: keys of --config, laid over them)\n"
         "  --prior-classes LIST   the size priors the geometric fit chooses among, comma-\n"
         "                         separated (geometric.classes), e.g. Sedan,SUV,Hatchback,Jeep,\n"
         "                         BoxTruck,SchoolBus for the simulator\n"
         "  --track                track the cuboids from frame to frame (docs/tracking.md):\n"
         "                         only the cuboids of born tracks are written, each with its\n"
         "                         track's id, velocity (velocity.linear, m/s, sensor frame)\n"
         "                         and class so far (label, and the share of the votes as\n"
         "                         score; the cuboid's own while no frame voted); the sensor's\n"
         "                         own motion is not taken out. Without it every cuboid is\n"
         "                         written, numbered per frame, at rest\n"
         "  --tracking-config FILE YAML file like config/tracking.yaml (implies --track)\n"
         "  --threads N            threads fitting a frame's objects (default: every core)\n"
         "  --overwrite            replace --out when a granular tool wrote it (a folder of\n"
         "                         other files is never replaced)\n"
         "  -h, --help             print this help and exit\n"
         "\n"
         "the ground (both --boxes) and the segmentation (--boxes segment):\n" +
         granular_ros::BoxFreeOptions::help() +
         "\n"
         "Progress goes to stderr, a summary to stdout: cuboids per label and the time per\n"
         "object in the fitter (median, p95, max). --out is built beside itself and put in\n"
         "place when complete; a second run into it is refused meanwhile. Exit status: 0 done,\n"
         "1 failed (unreadable input, output not writable or holding results without\n"
         "--overwrite), 2 bad option or configuration, 130/143/129 interrupted by\n"
         "SIGINT/SIGTERM/SIGHUP (nothing left half written).\n"
         "\n"
         "configuration keys (--config) and their defaults:\n" +
         granular_ros::configurationHelp<granular::CuboidConfig>() +
         "\n"
         "tracking keys (--tracking-config) and their defaults:\n" +
         granular_ros::configurationHelp<granular::TrackingConfig>();
}

struct Options {
  std::string frames;
  std::string out;
  std::optional<std::string> models;
  std::optional<std::string> method;
  std::optional<std::string> config_file;
  std::optional<std::string> boxes;
  std::optional<std::string> classifier_file;
  granular_ros::BoxFreeOptions box_free;
  std::optional<std::string> prior_classes;
  bool track = false;
  std::optional<std::string> tracking_config_file;
  int threads = 0;
  bool overwrite = false;
};

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::CuboidConfig config;
  granular::FitCuboidsOptions run;
  granular_ros::Tool tool("fit_cuboids", usage);
  tool.options()
      .flag("--overwrite", options.overwrite)
      .required("--frames", options.frames)
      .required("--out", options.out)
      .value("--models", options.models)
      .value("--method", options.method)
      .value("--config", options.config_file)
      .value("--boxes", options.boxes)
      .value("--classifier", options.classifier_file)
      .value("--prior-classes", options.prior_classes)
      .flag("--track", options.track)
      .value("--tracking-config", options.tracking_config_file)
      .threads("--threads", options.threads);
  options.box_free.addTo(tool.options());
  const auto configure = [&] {
    config = granular_ros::buildConfig<granular::CuboidConfig>(
        options.config_file, [&](granular::CuboidConfig& cuboids) {
          if (options.classifier_file && granular_ros::isVehicleDecision(*options.classifier_file)) {
            granular_ros::loadConfigFile(*options.classifier_file, cuboids);
          }
          if (options.method) {
            cuboids.method =
                granular_ros::parseChoice<granular::CuboidMethod>("--method", *options.method);
          }
          if (options.prior_classes) {
            cuboids.geometric.classes =
                granular_ros::splitList("--prior-classes", *options.prior_classes);
          }
        });
    options.box_free.frames = options.frames;  // whose clouds --sensor auto measures
    run.ground = options.box_free.ground();
    run.segmentation = options.box_free.segmentation();
    if (options.boxes) {
      run.boxes = granular_ros::parseChoice<granular::CuboidInputs>("--boxes", *options.boxes);
    }
    if (options.track || options.tracking_config_file) {
      run.tracking = granular_ros::buildConfig<granular::TrackingConfig>(
          options.tracking_config_file);
    }
    if (options.classifier_file && run.boxes != granular::CuboidInputs::kSegments) {
      throw std::invalid_argument("--classifier decides on segments: it needs --boxes segment");
    }
    if (config.method == granular::CuboidMethod::kModel && !options.models) {
      throw std::invalid_argument("the model method needs --models (or --method geometric)");
    }
  };
  std::optional<granular::SupervisedClassifier> classifier;
  return tool.run(argc, argv, configure, [&] {
    if (options.classifier_file && !granular_ros::isVehicleDecision(*options.classifier_file)) {
      classifier.emplace(granular_ros::loadBackgroundClassifier(
          *options.classifier_file, run.segmentation.background.label));
      run.classifier = &*classifier;
    }
    if (options.models && config.method == granular::CuboidMethod::kModel) {
      run.models = granular::readClassModels(*options.models);
    } else if (options.models) {
      std::cerr << "fit_cuboids: warning: --models is not used by the "
                << granular::config::enumName(config.method) << " method\n";
    }
    if (options.prior_classes && config.method != granular::CuboidMethod::kGeometric) {
      std::cerr << "fit_cuboids: warning: --prior-classes is not used by the "
                << granular::config::enumName(config.method) << " method\n";
    }
    // PCL prints a line for every registration that finds too few pairs.
    pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);
    run.threads = options.threads;
    run.output = granular_ros::Tool::outputPolicy(options.overwrite);
    run.progress = tool.progress("fitting", "frames");
    granular::fitCuboidsFolder(options.frames, options.out, config, run)
        .report(std::cout, std::cerr);
  });
}
