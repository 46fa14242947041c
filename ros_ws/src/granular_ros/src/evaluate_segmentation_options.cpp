#include "evaluate_segmentation_options.h"

#include <stdexcept>

#include "granular_ros/config_file.h"

namespace granular_ros {

void EvaluateSegmentationOptions::declareIn(Tool& tool) {
  tool.describe(
      "usage: evaluate_segmentation --frames FOLDER [options]\n\n"
      "Segments every cloud of a bag-to-files folder (pcd/<stamp>.pcd) without looking at\n"
      "its boxes, and compares the segments with the true boxes of detections_3d/\n"
      "<stamp>.json: greedy one-to-one matching of box centres in x-y, nearest first.\n"
      "Prints the recall (true objects of at least --min-points points with a segment\n"
      "centre within --max-distance), the footprint figure (with a segment centre inside\n"
      "their footprint: a box of the visible faces of a car seen from behind has its centre\n"
      "on the rear), the share of segments that match no true object, what each gate\n"
      "removed, and the time per cloud. Needs no roscore.\n",
      "Exit status: 0 done, 1 failed (unreadable input, a classifier without the Background\n"
      "class, --save folder not writable or holding results without --overwrite), 2 bad\n"
      "option or configuration, 130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP.\n\n"
      "configuration keys (--config) and their defaults:\n" +
          configurationHelp<granular::SegmentationStageConfig>() +
          "\nground configuration keys (--ground-config) and their defaults:\n" +
          configurationHelp<granular::GroundConfig>());
  tool.options().required("--frames", frames, "FOLDER", "bag-to-files folder");
  box_free.addTo(tool.options(), "--config");
  tool.options()
      .value("--method", method, "NAME",
             "objects (ground, range-aware grid, gates; default) or occupancy (the paper's grid "
             "on the whole cloud)")
      .value("--classifier", classifier_file, "FILE",
             "the Background decision: a train_classifier file trained with Background objects "
             "(extract_objects --background); the segments it calls Background with a score of "
             "at least background.min_score (1: unanimous) are dropped, except those beyond "
             "background.abstain_range with fewer than abstain_points points, and the figures "
             "are printed again for the rest")
      .value("--cuboids", cuboids_file, "FILE",
             "score full-vehicle cuboids instead of the segments' boxes: a YAML file like "
             "config/cuboids.yaml (geometric or rectangle method), fitted to each segment as "
             "fit_cuboids --boxes segment does; the time includes the fitting")
      .list("--prior-classes", prior_classes, "LIST",
            "with --cuboids: the size priors to choose among, comma-separated (KITTI: "
            "Car,Van,Truck; the simulator: Sedan,SUV,Hatchback,Jeep,BoxTruck,SchoolBus)")
      .value("--save", save, "FOLDER",
             "also write what the segmentation saw, per frame: <stamp>.json, the segments (or "
             "cuboids) as detections (label unknown, or --classifier's), and <stamp>.pcd, x y z "
             "with each point's height above the ground and its segment (-1 ground, 0 none, k+1 "
             "segment k), for render_frame")
      .flag("--overwrite", overwrite, "replace a --save folder a granular tool wrote")
      .number("--max-distance", evaluation.max_distance, "M",
              "metres between matched centres (default " + shown(evaluation.max_distance) + ")")
      .number("--min-points", evaluation.min_points, "N",
              "points a true box must hold to count (default " + shown(evaluation.min_points) +
                  ")")
      .number("--field-of-view", evaluation.half_field_of_view_deg, "DEG",
              "count objects and segments within DEG of straight ahead only, e.g. 40 for "
              "KITTI's camera-labelled frames (default " +
                  shown(evaluation.half_field_of_view_deg) + ": all around)")
      .number("--max-range", evaluation.max_range, "M",
              "count objects and segments nearer than M metres only");
}

granular::SegmentationStageConfig EvaluateSegmentationOptions::segmentation() const {
  granular::SegmentationStageConfig config = box_free.segmentation();
  if (method) {
    config.method = parseChoice<granular::SegmentationMethod>("--method", *method);
  }
  return config;
}

std::optional<granular::CuboidConfig> EvaluateSegmentationOptions::cuboids() const {
  if (!prior_classes.empty() && !cuboids_file) {
    throw std::invalid_argument("--prior-classes chooses the cuboids' priors: it needs --cuboids");
  }
  if (!cuboids_file) {
    return std::nullopt;
  }
  const auto cuboids = buildConfig<granular::CuboidConfig>(
      cuboids_file, [&](granular::CuboidConfig& loaded) {
        if (!prior_classes.empty()) {
          loaded.geometric.classes = prior_classes;
        }
      });
  if (cuboids.method == granular::CuboidMethod::kModel) {
    throw std::invalid_argument(
        "--cuboids: the model method needs class models; use method geometric or rectangle");
  }
  return cuboids;
}

void EvaluateSegmentationOptions::checkFigures() const {
  if (!(evaluation.max_distance >= 0.0) || !(evaluation.half_field_of_view_deg > 0.0) ||
      !(evaluation.max_range > 0.0)) {
    throw std::invalid_argument(
        "--max-distance must not be negative, --field-of-view and --max-range positive");
  }
}

}  // namespace granular_ros
