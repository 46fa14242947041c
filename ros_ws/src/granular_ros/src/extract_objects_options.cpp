#include "extract_objects_options.h"

#include "granular_ros/config_file.h"

namespace granular_ros {

void ExtractObjectsOptions::declareIn(Tool& tool) {
  const granular::ExtractionConfig defaults;
  tool.describe(
      "usage: extract_objects --in FOLDER --out FOLDER [options]\n\n"
      "Crops the LiDAR points of every 3-D detection of a bag-to-files folder (pcd/<stamp>.pcd\n"
      "paired with detections_3d/<stamp>.json) and writes each object as a binary PCD in its\n"
      "own frame (origin at the centre of the box's bottom face, x along its length, z up),\n"
      "named <Label>-<stamp>-<index>.pcd (index: 1, 2, ... over that label's detections in\n"
      "the frame; in the label every byte but letters, digits, '_' and '.' is written %XX,\n"
      "so 'Tram_/_Subway' is Tram_%2F_Subway), with an index.csv per objects folder holding\n"
      "the labels as given. Boxes larger than max_box_size (" +
          shown(static_cast<int>(defaults.max_box_size)) +
          " m) are skipped as implausible.\nNeeds no roscore.\n",
      "Progress goes to stderr, the summary (objects per label and threshold, frames/s) to\n"
      "stdout. --out is built beside itself and put in place when complete; a second run\n"
      "into it is refused meanwhile. Exit status: 0 done, 1 extraction failed (unreadable\n"
      "input, output not writable or holding results without --overwrite), 2 bad option or\n"
      "configuration, 130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP (nothing left half\n"
      "written).\n\nconfiguration keys (--config) and their defaults:\n" +
          configurationHelp(defaults));
  tool.options()
      .required("--in", in, "FOLDER", "bag-to-files folder to read")
      .required("--out", out, "FOLDER",
                "objects folder to create; with several thresholds it holds one complete "
                "objects folder N<thresh>/ per threshold")
      .numbers("--n-thresh", n_thresh, "LIST",
               "minimum points per object, comma-separated, e.g. 10,50,100,300,500 (default " +
                   joinedNumbers(defaults.n_thresh) + ")")
      .value("--boxes", boxes, "FOLDER",
             "take the boxes from FOLDER/<stamp>.json (fit_cuboids' output, for a bag without "
             "boxes) instead of the frames' detections_3d/")
      .flag("--background", background,
            "also extract Background objects for training: every frame is segmented as the "
            "box-free path does, and the segments on no true box are written under the label "
            "of --segmentation-config's background section (docs/segmentation.md); with the "
            "five options below and --segment-objects");
  box_free.addTo(tool.options());
  tool.options()
      .flag("--segment-objects", segment_objects,
            "with --background, the other classes' objects are segments too: each segment with "
            "at least background.min_object_share of its points on one true box, in its "
            "segment's box under that box's label, instead of the true boxes' crops (what the "
            "box-free path will show a classifier)")
      .flag("--threshold-folders", threshold_folders,
            "write N<thresh>/ inside --out even for a single threshold")
      .list("--labels", labels, "LIST",
            "labels to extract, comma-separated, e.g. Sedan,SUV (default: all)")
      .numbers("--padding", padding, "X,Y,Z",
               "metres added on each side of a box along its length, width and height "
               "(default " + joinedNumbers(defaults.padding) + ")",
               3)
      .value("--config", config_file, "FILE",
             "YAML file with padding, n_thresh, labels and max_box_size (the repository's "
             "config/extraction.yaml documents them); options above override it")
      .flag("--overwrite", overwrite,
            "replace --out when a granular tool wrote it (a folder of other files is never "
            "replaced)");
}

granular::ExtractionConfig ExtractObjectsOptions::config() const {
  return buildConfig<granular::ExtractionConfig>(
      config_file, [&](granular::ExtractionConfig& loaded) {
        if (!n_thresh.empty()) {
          loaded.n_thresh = n_thresh;
        }
        if (!labels.empty()) {
          loaded.labels = labels;
        }
        if (!padding.empty()) {
          loaded.padding = Eigen::Vector3d(padding[0], padding[1], padding[2]);
        }
      });
}

}  // namespace granular_ros
