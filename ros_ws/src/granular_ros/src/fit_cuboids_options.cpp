#include "fit_cuboids_options.h"

#include <stdexcept>

#include <granular_core/extraction/extraction_config.h>
#include <granular_core/tracking/tracking_config.h>

#include "granular_ros/config_file.h"

namespace granular_ros {

void FitCuboidsOptions::declareIn(Tool& tool) {
  tool.describe(
      "usage: fit_cuboids --frames FOLDER --out FOLDER [options]\n"
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
      "describes them and what they measured. Needs no roscore.\n",
      "The ground under both --boxes comes from --ground-config, --sensor and --sensor-height;\n"
      "the segmentation of --boxes segment from --segmentation-config, --sensor and\n"
      "--azimuth-step.\n\n"
      "Progress goes to stderr, a summary to stdout: cuboids per label and the time per\n"
      "object in the fitter (median, p95, max). --out is built beside itself and put in\n"
      "place when complete; a second run into it is refused meanwhile. Exit status: 0 done,\n"
      "1 failed (unreadable input, a cloud not in the sensor's frame, output not writable\n"
      "or holding results without --overwrite), 2 bad option or configuration,\n"
      "130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP (nothing left half written).\n"
      "\n"
      "configuration keys (--config) and their defaults:\n" +
      configurationHelp<granular::CuboidConfig>() +
      "\n"
      "tracking keys (--tracking-config) and their defaults:\n" +
      configurationHelp<granular::TrackingConfig>());
  tool.options()
      .required("--frames", frames, "FOLDER", "bag-to-files folder")
      .required("--out", out, "FOLDER", "folder of <stamp>.json to create")
      .value("--models", models, "FOLDER",
             "class models (<Class>.pcd, as build_models writes them)")
      .value("--method", method, "NAME",
             "geometric, model or rectangle (default: the config's method)")
      .value("--config", config_file, "FILE", "YAML file like config/cuboids.yaml")
      .value("--boxes", boxes, "WHAT",
             "segment (default; the zero-shot vehicle decision keeps the vehicles, or "
             "--classifier decides) or detections")
      .value("--classifier", classifier_file, "FILE",
             "--boxes segment: the Background decision, a train_classifier file trained with "
             "Background objects (extract_objects --background); the segments it calls "
             "Background with a score of at least background.min_score (1: unanimous) get no "
             "cuboid; far sparse segments are kept (see background.abstain_points and "
             "abstain_range); the others' cuboids take its class and score as label (where the "
             "method gives none: geometric, rectangle), unknown where its answer was a "
             "Background not sure enough to drop; or a vehicle decision that "
             "train_vehicle_decision tuned on labelled frames (the evidence: keys of --config, "
             "laid over them)")
      .value("--name-with", name_with, "METHOD",
             "name each cuboid with a classifier (icp, icp_nl, ndt, knn, svm, svm_esf or "
             "svm_fitness): the frame's points in the cuboid, in its object frame as "
             "extract_objects crops a given box (turned to face away from the sensor, as "
             "label_box_free turns training objects), classified; its label and score replace "
             "the fitter's and --classifier's (not where the object has too few points for the "
             "method)")
      .value("--name-models", name_models, "PATH",
             "--name-with: the class models folder (icp, icp_nl, ndt) or the train_classifier "
             "file (the others)")
      .value("--class-models", class_models, "FOLDER",
             "--name-with svm_fitness: the class models it learnt from")
      .value("--preset", preset, "NAME",
             "--name-with: registration parameters of --registration-config (default: tuned)")
      .value("--registration-config", registration_config, "FILE",
             "YAML file like config/classification.yaml")
      .value("--extraction-config", extraction_config, "FILE",
             "YAML file like config/extraction.yaml: its padding grows the cuboids --name-with "
             "crops (default: none)")
      .list("--prior-classes", prior_classes, "LIST",
            "the size priors the geometric fit chooses among, comma-separated "
            "(geometric.classes), e.g. Sedan,SUV,Hatchback,Jeep,BoxTruck,SchoolBus for the "
            "simulator")
      .flag("--track", track,
            "track the cuboids from frame to frame (docs/tracking.md): only the cuboids of born "
            "tracks are written, each with its track's id, velocity (velocity.linear, m/s, "
            "sensor frame) and class (label, and the share of the votes as score: of all the "
            "track's frames with the config's final_class, the default, else of its frames so "
            "far; the cuboid's own where no frame voted); the sensor's own motion is not taken "
            "out. Without it every cuboid is written, numbered per frame, at rest")
      .value("--tracking-config", tracking_config_file, "FILE",
             "YAML file like config/tracking.yaml (implies --track)")
      .threads("--threads", threads, "threads fitting a frame's objects (default: every core)")
      .flag("--allow-other-frames", allow_other_frames,
            "go on when a cloud's road is not where the sensor's frame puts it (ground "
            "sensor_frame: a world or vehicle frame), naming each such frame among those "
            "without ground; without it the first such frame stops the run (exit 1)")
      .flag("--overwrite", overwrite,
            "replace --out when a granular tool wrote it (a folder of other files is never "
            "replaced)");
  box_free.addTo(tool.options());
}

granular::CuboidConfig FitCuboidsOptions::config() const {
  return buildConfig<granular::CuboidConfig>(config_file, [&](granular::CuboidConfig& cuboids) {
    if (classifier_file && isVehicleDecision(*classifier_file)) {
      loadConfigFile(*classifier_file, cuboids);
    }
    if (method) {
      cuboids.method = parseChoice<granular::CuboidMethod>("--method", *method);
    }
    if (!prior_classes.empty()) {
      cuboids.geometric.classes = prior_classes;
    }
  });
}

void FitCuboidsOptions::configure(granular::FitCuboidsOptions& run,
                                  const granular::CuboidConfig& config) {
  box_free.frames = frames;  // whose clouds --sensor auto measures
  run.ground = box_free.ground();
  run.segmentation = box_free.segmentation();
  if (boxes) {
    run.boxes = parseChoice<granular::CuboidInputs>("--boxes", *boxes);
  }
  if (track || tracking_config_file) {
    run.tracking = buildConfig<granular::TrackingConfig>(tracking_config_file);
  }
  if (classifier_file && run.boxes != granular::CuboidInputs::kSegments) {
    throw std::invalid_argument("--classifier decides on segments: it needs --boxes segment");
  }
  if (name_with && !name_models) {
    throw std::invalid_argument("--name-with needs --name-models");
  }
  if (!name_with && (name_models || class_models)) {
    throw std::invalid_argument("--name-models and --class-models go with --name-with");
  }
  if (name_with && !granular::registrationMethodFromName(*name_with) &&
      !granular::supervisedMethodFromName(*name_with) && *name_with != "svm_fitness") {
    throw std::invalid_argument(
        "--name-with: expected icp, icp_nl, ndt, knn, svm, svm_esf or svm_fitness, got '" +
        *name_with + "'");
  }
  if (name_with && *name_with == "svm_fitness" && !class_models) {
    throw std::invalid_argument(
        "--name-with svm_fitness needs --class-models, the models folder it learnt from");
  }
  if (extraction_config) {
    run.naming_padding = buildConfig<granular::ExtractionConfig>(extraction_config).padding;
  }
  if (config.method == granular::CuboidMethod::kModel && !models) {
    throw std::invalid_argument("the model method needs --models (or --method geometric)");
  }
}

}  // namespace granular_ros
