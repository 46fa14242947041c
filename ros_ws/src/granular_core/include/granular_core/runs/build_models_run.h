#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "granular_core/dataset/output_folder.h"
#include "granular_core/models/class_model.h"
#include "granular_core/models/model_config.h"

namespace granular {

/// How buildModels runs, apart from the tunables.
struct BuildModelsOptions {
  /// Whether an output folder of an earlier run may be replaced (see OutputFolder).
  OutputPolicy output;
  /// Classes to build; empty builds every class of the objects folder.
  std::vector<std::string> classes;
  /// ICP seed PCD by class; classes without one get an automatic seed.
  std::map<std::string, std::filesystem::path> seeds;
  /// Also write OUT/mesh/<Class>.ply.
  bool mesh = false;
  /// Called with (class, objects aligned, objects to align) during ICP; may be empty.
  std::function<void(const std::string&, std::size_t, std::size_t)> progress;
  /// Called with each class's summary when it is done; may be empty.
  std::function<void(const ClassModelSummary&)> class_done;
};

/// What buildModels did.
struct BuildModelsSummary {
  std::vector<ClassModelSummary> classes;  ///< in class name order, left-out ones included
  /// The classes that got no model (too few objects or points, see ModelBuildConfig's
  /// min_objects and min_points) and why, by class.
  std::map<std::string, std::string> left_out;
  std::vector<std::string> warnings;       ///< about the run as a whole
  std::vector<std::string> cleared;  ///< what dead runs had left and was cleared
  ConcatenationMethod method = ConcatenationMethod::kPlain;
  double seconds = 0.0;  ///< wall time of the whole run

  /// One class's line (objects, kept, points, seconds) and its warnings on `log`, as it is done.
  static void reportClass(const ClassModelSummary& model, std::ostream& log);
  /// What was cleared and the warnings on `log`; the points after each filter stage of every
  /// class as a table on `out`.
  void report(std::ostream& out, std::ostream& log) const;
};

/// Builds the model of every class (or of options.classes) of the objects folder `objects`
/// (see listObjectFiles) into the folder `out`:
///   - `out/<Class>.pcd`: the filtered model, binary PCD with fields x y z (writeModelPcd);
///   - `out/raw/<Class>.pcd`: the concatenation before filtering;
///   - `out/mesh/<Class>.ply`: with options.mesh, the filtered model's mesh (triangulate);
///   - `out/models.json`: per class the objects used and kept, the ICP seed and verdicts, the
///     points after each stage, the filter parameters used and the seconds taken, plus the
///     method and ICP parameters of the run.
/// A class with fewer than config.min_objects objects (none, for a requested class that is not
/// there) or whose filtered model has fewer than config.min_points points is left out: named
/// with the reason in the summary's left_out and warnings and in models.json ("left_out"), and
/// it gets no files.
///
/// `out` is an OutputFolder: locked, built in a hidden sibling and renamed into place at the
/// end, so a failure or a signal leaves `out` as it was. Throws std::invalid_argument for a bad config, and
/// std::runtime_error (naming the file or folder) for a missing objects folder, a folder
/// without object PCDs, an unreadable object or seed PCD, a seed for a class not built, no
/// class with objects among those requested, no class left with a model (the reasons named),
/// an `out` that may not be replaced (see
/// checkOutputFolder), and write failures.
BuildModelsSummary buildModels(const std::filesystem::path& objects,
                               const std::filesystem::path& out, const ModelBuildConfig& config,
                               const BuildModelsOptions& options = {});

}  // namespace granular
