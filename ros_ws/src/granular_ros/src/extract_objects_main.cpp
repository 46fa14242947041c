// extract_objects: the command-line face of granular::extractFolder. Reads options and an
// optional YAML config, runs the extraction, reports progress on stderr and a summary on stdout.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <granular_core/extraction/extract_folder.h>

#include "granular_ros/command_line.h"
#include "granular_ros/extraction_config_yaml.h"
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
         "  --help            print this help and exit\n"
         "\n"
         "Progress goes to stderr, the summary (objects per label and threshold, frames/s) to\n"
         "stdout. --out is built beside itself and put in place when complete; a second run\n"
         "into it is refused meanwhile. Exit status: 0 done, 1 extraction failed (unreadable\n"
         "input, output not writable or holding results without --overwrite), 2 bad option or\n"
         "configuration, 130/143 interrupted (nothing left half written).\n";
}

struct Options {
  std::string in;
  std::string out;
  std::optional<std::string> config_file;
  std::optional<std::string> n_thresh;
  std::optional<std::string> labels;
  std::optional<std::string> padding;
  bool overwrite = false;
  bool threshold_folders = false;
};

// Defaults, then the YAML file, then the command line.
granular::ExtractionConfig buildConfig(const Options& options) {
  granular::ExtractionConfig config;
  if (options.config_file) {
    granular_ros::loadExtractionConfig(*options.config_file, config);
  }
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
    const std::vector<std::string> items = granular_ros::splitList("--padding", *options.padding);
    if (items.size() != 3) {
      throw std::invalid_argument("--padding: expected X,Y,Z in metres, got '" + *options.padding + "'");
    }
    for (std::size_t axis = 0; axis < 3; ++axis) {
      config.padding[static_cast<Eigen::Index>(axis)] =
          granular_ros::parseNumber<double>("--padding", items[axis]);
    }
  }
  try {
    granular::validate(config);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(std::string("invalid configuration: ") + error.what());
  }
  return config;
}

void reportList(const char* title, const std::vector<std::string>& lines) {
  constexpr std::size_t kShown = 10;
  if (lines.empty()) {
    return;
  }
  std::cerr << title << " (" << lines.size() << "):\n";
  for (std::size_t i = 0; i < lines.size() && i < kShown; ++i) {
    std::cerr << "  " << lines[i] << '\n';
  }
  if (lines.size() > kShown) {
    std::cerr << "  ... and " << lines.size() - kShown << " more\n";
  }
}

void printSummary(const granular::ExtractFolderSummary& summary, double seconds) {
  reportList("cleared", summary.cleared);
  reportList("warnings", summary.warnings);
  reportList("frames skipped", summary.frames_skipped);
  reportList("invalid detections skipped", summary.invalid_detections);

  std::printf("frames: %zu extracted, %zu skipped, %.2f s, %.1f frames/s\n", summary.frames_read,
              summary.frames_skipped.size(), seconds,
              seconds > 0.0 ? static_cast<double>(summary.frames_read) / seconds : 0.0);
  std::printf("invalid detections: %zu, non-finite points: %zu\n",
              summary.invalid_detections.size(), summary.non_finite_points);

  std::map<std::string, std::map<std::size_t, std::size_t>> by_label;
  for (const auto& [threshold, labels] : summary.objects) {
    for (const auto& [label, count] : labels) {
      by_label[label][threshold] = count;
    }
  }
  // The label column as wide as the longest label, so that long real labels keep the table.
  int width = 16;
  for (const auto& [label, counts] : by_label) {
    width = std::max(width, static_cast<int>(label.size()));
  }
  std::printf("objects per label (columns: at least N points):\n  %-*s", width, "label");
  for (const auto& [threshold, labels] : summary.objects) {
    std::printf(" %8s", ("N" + std::to_string(threshold)).c_str());
  }
  std::printf("\n");
  std::map<std::size_t, std::size_t> totals;
  for (const auto& [label, counts] : by_label) {
    std::printf("  %-*s", width, label.c_str());
    for (const auto& [threshold, labels] : summary.objects) {
      const auto count = counts.find(threshold);
      const std::size_t value = count == counts.end() ? 0 : count->second;
      totals[threshold] += value;
      std::printf(" %8zu", value);
    }
    std::printf("\n");
  }
  std::printf("  %-*s", width, "total");
  for (const auto& [threshold, labels] : summary.objects) {
    std::printf(" %8zu", totals[threshold]);
  }
  std::printf("\n");
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
      .value("--padding", options.padding);
  return tool.run(argc, argv, [&] { config = buildConfig(options); }, [&] {
    granular::ExtractFolderOptions run;
    run.output = granular_ros::Tool::outputPolicy(options.overwrite);
    run.threshold_folders = options.threshold_folders;
    run.progress = tool.progress("extracting", "frames");
    const auto start = std::chrono::steady_clock::now();
    const granular::ExtractFolderSummary summary =
        granular::extractFolder(options.in, options.out, config, run);
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    printSummary(summary, elapsed.count());
  });
}
