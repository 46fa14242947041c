#pragma once

#include <optional>
#include <string>
#include <vector>

#include <granular_core/extraction/extraction_config.h>

#include "granular_ros/box_free_options.h"
#include "granular_ros/tool.h"

namespace granular_ros {

/// extract_objects' command line: its options, each declared once with its help, and the
/// --help text around them.
struct ExtractObjectsOptions {
  std::string in;
  std::string out;
  std::string boxes;
  std::optional<std::string> config_file;
  std::vector<std::size_t> n_thresh;
  std::vector<std::string> labels;
  std::vector<double> padding;
  bool background = false;
  bool segment_objects = false;
  bool threshold_folders = false;
  bool overwrite = false;
  BoxFreeOptions box_free;

  /// Describes the tool and binds these fields to its options.
  void declareIn(Tool& tool);
  /// The extraction's configuration: defaults, --config, then the options above.
  granular::ExtractionConfig config() const;
};

}  // namespace granular_ros
