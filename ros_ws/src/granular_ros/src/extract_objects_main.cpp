// extract_objects: the command-line face of granular::extractFolder (its options:
// extract_objects_options.h).
#include <iostream>
#include <stdexcept>

#include <granular_core/runs/extract_run.h>

#include "extract_objects_options.h"

int main(int argc, char** argv) {
  granular_ros::ExtractObjectsOptions options;
  granular::ExtractionConfig config;
  granular::ExtractFolderOptions run;
  granular_ros::Tool tool("extract_objects");
  options.declareIn(tool);
  const auto configure = [&] {
    config = options.config();
    if (options.background) {
      options.box_free.frames = options.in;  // whose clouds --sensor auto measures
      run.background = granular::BackgroundHarvest{
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
    run.output = granular_ros::Tool::outputPolicy(options.overwrite);
    run.threshold_folders = options.threshold_folders;
    run.boxes = options.boxes;
    run.progress = tool.progress("extracting", "frames");
    granular::extractFolder(options.in, options.out, config, run).report(std::cout, std::cerr);
  });
}
