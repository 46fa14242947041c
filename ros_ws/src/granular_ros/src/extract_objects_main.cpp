// extract_objects: the command-line face of granular::extractFolder. Reads options and an
// optional YAML config, runs the extraction, reports progress on stderr and a summary on stdout.
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/runs/extract_run.h>

#include "granular_ros/box_free_options.h"
#include "granular_ros/command_line.h"
#include "granular_ros/config_file.h"
#include "granular_ros/tool.h"

namespace {

// "a,b,c" of a container's values, for --help.
template <typename T>
std::string joinValues(const T& values) {
  std::ostringstream text;
  for (const auto value : values) {
    text << (text.tellp() > 0 ? "," : "") << value;
  }
  return text.str();
}

std::string usage() {
  const granular::ExtractionConfig defaults;
  return "usage: extract_objects --in FOLDER --out FOLDER [options]\n"
         "\n"
         "Crops the LiDAR points of every 3-D detection of a bag-to-files folder (pcd/<stamp>.pcd\n"
         "paired with detections_3d/<stamp>.json) and writes each object as a binary PCD in its\n"
         "own frame (origin at the centre of the box's bottom face, x along its length, z up),\n"
         "named <Label>-<stamp>-<index>.pcd (index: 1, 2, ... over that label's detections in\n"
         "the frame; in the label every byte but letters, digits, '_' and '.' is written %XX,\n"
         "so 'Tram_/_Subway' is Tram_%2F_Subway), with an index.csv per objects folder holding\n"
         "the labels as given. Boxes larger than max_box_size (" +
         std::to_string(static_cast<int>(defaults.max_box_size)) +
         " m) are skipped as implausible.\n"
         "Needs no roscore.\n"
         "\n"
         "options:\n"
         "  --in FOLDER       bag-to-files folder to read\n"
         "  --out FOLDER      objects folder to create; with several thresholds it holds one\n"
         "                    complete objects folder N<thresh>/ per threshold\n"
         "  --n-thresh LIST   minimum points per object, comma-separated, e.g. 10,50,100,300,500\n"
         "                    (default " + joinValues(defaults.n_thresh) + ")\n"
         "  --boxes FOLDER    take the boxes from FOLDER/<stamp>.json (fit_cuboids' output, for\n"
         "                    a bag without boxes) instead of the frames' detections_3d/\n"
         "  --background      also extract Background objects for training: every frame is\n"
         "                    segmented as the box-free path does, and the segments on no\n"
         "                    true box are written under the label of --segmentation-config's\n"
         "                    background section (docs/segmentation.md); with:\n" +
         granular_ros::BoxFreeOptions::help() +
         "  --segment-objects with --background, the other classes' objects are segments too:\n"
         "                    each segment with at least background.min_object_share of its\n"
         "                    points on one true box, in its segment's box under that box's\n"
         "                    label, instead of the true boxes' crops (what the box-free path\n"
         "                    will show a classifier)\n" +
         "  --threshold-folders\n"
         "                    write N<thresh>/ inside --out even for a single threshold\n"
         "  --labels LIST     labels to extract, comma-separated, e.g. Sedan,SUV (default: all)\n"
         "  --padding X,Y,Z   metres added on each side of a box along its length, width and\n"
         "                    height (default " + joinValues(defaults.padding) + ")\n"
         "  --config FILE     YAML file with padding, n_thresh, labels and max_box_size (the\n"
         "                    repository's config/extraction.yaml documents them); options\n"
         "                    above override it\n"
         "  --overwrite       replace --out when a granular tool wrote it (a folder of other\n"
         "                    files is never replaced)\n"
         "  -h, --help        print this help and exit\n"
         "\n"
         "Progress goes to stderr, the summary (objects per label and threshold, frames/s) to\n"
         "stdout. --out is built beside itself and put in place when complete; a second run\n"
         "into it is refused meanwhile. Boxes must be in their cloud's frame (a box whose\n"
         "header.frame_id is not its file's is refused: bag_to_files moves boxes into the\n"
         "cloud's frame with the bag's /tf and /tf_static). Exit status: 0 done, 1 extraction\n"
         "failed (unreadable input, a box in another frame than its cloud, output not writable\n"
         "or holding results without --overwrite), 2 bad option or configuration,\n"
         "130/143/129 interrupted by SIGINT/SIGTERM/SIGHUP (nothing left half written).\n"
         "\n"
         "configuration keys (--config) and their defaults:\n" +
         granular_ros::configurationHelp<granular::ExtractionConfig>();
}

struct Options {
  std::string in;
  std::string out;
  std::optional<std::string> config_file;
  std::optional<std::string> n_thresh;
  std::optional<std::string> labels;
  std::optional<std::string> padding;
  std::string boxes;
  bool background = false;
  bool segment_objects = false;
  granular_ros::BoxFreeOptions box_free;
  bool overwrite = false;
  bool threshold_folders = false;
};

// Defaults, then the YAML file, then the command line.
granular::ExtractionConfig buildExtractionConfig(const Options& options) {
  return granular_ros::buildConfig<granular::ExtractionConfig>(
      options.config_file, [&](granular::ExtractionConfig& config) {
        if (options.n_thresh) {
          config.n_thresh.clear();
          for (const std::string& item : granular_ros::splitList("--n-thresh", *options.n_thresh)) {
            config.n_thresh.push_back(granular_ros::parseNumber<std::size_t>("--n-thresh", item));
          }
        }
        if (options.labels) {
          config.labels = granular_ros::splitList("--labels", *options.labels);
        }
        if (options.padding) {
          const std::vector<std::string> items =
              granular_ros::splitList("--padding", *options.padding);
          if (items.size() != 3) {
            throw std::invalid_argument("--padding: expected X,Y,Z in metres, got '" +
                                        *options.padding + "'");
          }
          for (Eigen::Index axis = 0; axis < 3; ++axis) {
            config.padding[axis] = granular_ros::parseNumber<double>(
                "--padding", items[static_cast<std::size_t>(axis)]);
          }
        }
      });
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  granular::ExtractionConfig config;
  granular_ros::Tool tool("extract_objects", usage);
  tool.options()
      .flag("--overwrite", options.overwrite)
      .flag("--threshold-folders", options.threshold_folders)
      .required("--in", options.in)
      .required("--out", options.out)
      .value("--config", options.config_file)
      .value("--n-thresh", options.n_thresh)
      .value("--labels", options.labels)
      .value("--padding", options.padding)
      .value("--boxes", options.boxes)
      .flag("--background", options.background)
      .flag("--segment-objects", options.segment_objects);
  options.box_free.addTo(tool.options());
  std::optional<granular::BackgroundHarvest> background;
  const auto configure = [&] {
    config = buildExtractionConfig(options);
    if (options.background) {
      options.box_free.frames = options.in;  // whose clouds --sensor auto measures
      background = granular::BackgroundHarvest{
          options.box_free.ground(), options.box_free.segmentation(), options.segment_objects};
    } else if (options.segment_objects) {
      throw std::invalid_argument("--segment-objects goes with --background");
    } else if (options.box_free.given()) {
      throw std::invalid_argument(
          "--ground-config, --segmentation-config, --sensor, --sensor-height and "
          "--azimuth-step go with --background");
    }
  };
  return tool.run(argc, argv, configure, [&] {
    granular::ExtractFolderOptions run;
    run.output = granular_ros::Tool::outputPolicy(options.overwrite);
    run.threshold_folders = options.threshold_folders;
    run.boxes = options.boxes;
    run.background = background;
    run.progress = tool.progress("extracting", "frames");
    granular::extractFolder(options.in, options.out, config, run).report(std::cout, std::cerr);
  });
}
