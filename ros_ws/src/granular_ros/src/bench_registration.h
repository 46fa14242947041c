#pragma once

#include <optional>
#include <string>
#include <vector>

#include <granular_core/registration/registration_config.h>

#include "granular_ros/tool.h"

namespace granular_ros {

/// bench_registration's command line: its options, each declared once with its help, and the
/// --help text around them. (Its two comparisons below: the main is the options and a choice.)
struct BenchRegistrationOptions {
  std::string models;
  std::string objects;
  std::vector<std::string> methods = {"icp", "icp_nl", "ndt"};
  std::string preset;
  std::optional<std::string> config_file;
  int threads = 0;
  std::optional<std::string> end_to_end;  ///< folder for the whole runs' JSON files
  bool early_rejection = false;

  /// Describes the tool and binds these fields to its options.
  void declareIn(Tool& tool);
};

/// Each method's registration of the objects, the report's loop against granular's, in one
/// process; prints a table. False when ICP's or NDT's predictions differ (they must not).
bool compareLoops(const BenchRegistrationOptions& options,
                  const granular::RegistrationClassifierConfig& config);

/// --end-to-end: each method's whole run, reading the files to the JSON written, granular's
/// against the plain loop's; prints a table. False as compareLoops.
bool compareWholeRuns(const BenchRegistrationOptions& options,
                      const granular::RegistrationClassifierConfig& config);

}  // namespace granular_ros
