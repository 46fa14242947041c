#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <granular_core/dataset/output_folder.h>

#include "granular_ros/command_line.h"

namespace granular_ros {

/// Exit statuses every tool shares (their --help lists them); a signal gives 128 + its number.
constexpr int kExitDone = 0;
constexpr int kExitFailed = 1;
constexpr int kExitBadUsage = 2;

/// A problem with what the user asked for that only shows once work has started (a classifier
/// file trained with other settings than the config given): Tool::run exits 2 for it.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws a UsageError saying `problem`, unless it is empty (nothing is wrong).
inline void refuseIfProblem(const std::string& problem) {
  if (!problem.empty()) {
    throw UsageError(problem);
  }
}

/// The skeleton of every command-line tool: its options, --help, exit statuses, progress and
/// error reporting, and a clean stop on a signal.
///
///   Tool tool("extract_objects", "usage: extract_objects --in FOLDER ...\n\nWhat it does.\n",
///             "Exit status: ...\n");
///   tool.options().required("--in", options.in, "FOLDER", "bag-to-files folder to read") ... ;
///   return tool.run(argc, argv, [&] { config = buildConfig(options); }, [&] { ... });
class Tool {
 public:
  /// --help (and -h) prints `about` (the usage lines and what the tool does), "options:" with
  /// the option table's lines (OptionTable::help), and `epilogue` (exit statuses, configuration
  /// keys).
  Tool(std::string name, std::string about, std::string epilogue);
  /// A tool whose help text describe() gives (a tool's options unit, when they outgrow its
  /// main).
  explicit Tool(std::string name) : Tool(std::move(name), "", "") {}

  /// Sets what --help prints around the options (the constructor's `about` and `epilogue`).
  void describe(std::string about, std::string epilogue) {
    about_ = std::move(about);
    epilogue_ = std::move(epilogue);
  }

  OptionTable& options() { return options_; }
  /// The help flag, bound into options() by the constructor.
  bool helpRequested() const { return help_; }

  /// Stops cleanly on SIGINT, SIGTERM and SIGHUP (removing partial output, see
  /// granular::removePendingOutputs; exit 130, 143, 129 with one line), parses the options and
  /// runs `configure` (problems there and in the options: "NAME: message" and exit 2) and then
  /// `work` (an exception: "NAME: message" and exit 1, 2 for a UsageError). Returns the exit
  /// status.
  int run(int argc, char** argv, const std::function<void()>& configure,
          const std::function<void()>& work);

  /// A progress callback for long work: "WHAT: DONE/TOTAL UNIT (P%)" on stderr.
  std::function<void(std::size_t, std::size_t)> progress(const std::string& what,
                                                         const std::string& unit,
                                                         std::size_t lines = 10) const;

  /// "NAME: warning: WARNING" on stderr for each of `warnings`.
  void warn(const std::vector<std::string>& warnings) const;

  /// The output policy of `--overwrite`: its error names "--overwrite", or what the environment
  /// variable GRANULAR_OVERWRITE_HINT says (a launch file's "overwrite:=true").
  static granular::OutputPolicy outputPolicy(bool overwrite);

  const std::string& name() const { return name_; }

 private:
  std::string name_;
  std::string about_;
  std::string epilogue_;
  OptionTable options_;
  bool help_ = false;
};

/// Blocks SIGINT, SIGTERM and SIGHUP in this thread and every thread started after (call it
/// before any other thread starts), and watches for them in a thread of its own: on the first,
/// the pending outputs are removed, "NAME: interrupted by SIGxxx; partial output removed" is
/// printed and the process exits with 128 + the signal's number. Tool::run calls it.
void stopCleanlyOnSignals(const std::string& name);

/// Keeps the memory a frame frees for the next frame: no block of up to 32 MiB is mapped
/// for itself, and none of what is freed is handed back to the system below 256 MiB. By
/// default glibc returns a 120,000-point frame's buffers between frames, and every frame
/// then pays about 2,400 page faults to get them back (2 ms of fit_cuboids' 18 ms a KITTI
/// frame). Tool::run calls it; the nodes that take clouds call it first.
void reuseFreedMemory();

}  // namespace granular_ros
