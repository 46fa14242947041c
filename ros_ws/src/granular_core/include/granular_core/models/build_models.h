#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "granular_core/dataset/output_folder.h"
#include "granular_core/models/filter_chain.h"
#include "granular_core/models/model_cloud.h"
#include "granular_core/models/model_config.h"

namespace granular {

/// What building one class model did.
struct ClassModelSummary {
  std::string label;
  std::size_t objects = 0;  ///< object clouds of the class
  /// Objects in the raw model: all of them for plain concatenation; for ICP the seed objects
  /// plus the objects whose alignment was kept.
  std::size_t kept = 0;
  /// ICP only: "auto" (SeedConfig) or the seed PCD given for the class.
  std::string seed_source;
  std::vector<std::size_t> seed_objects;  ///< ICP, auto seed: indices into the class's objects
  std::vector<std::string> missing_sides; ///< ICP, auto seed: sides no object shows
  std::size_t seed_points = 0;            ///< ICP: points of the seed
  std::map<std::string, std::size_t> verdicts;     ///< ICP: objects per verdictName
  std::map<std::string, std::size_t> convergence;  ///< ICP: aligned objects per convergenceName
  std::size_t raw_points = 0;
  FilterChainConfig filters;        ///< the chain used (shared chain with class overrides)
  std::vector<StageResult> stages;  ///< points after each stage
  std::size_t points = 0;           ///< points of the filtered model
  std::size_t mesh_polygons = 0;    ///< with a mesh
  double seconds = 0.0;             ///< wall time of concatenation and filtering
  std::vector<std::string> warnings;
};

/// A class model: its raw (concatenated) and filtered clouds.
struct ClassModel {
  ClassModelSummary summary;
  ModelCloud raw;
  ModelCloud model;
};

/// Builds the model of class `label` from its object clouds: concatenation by config.method,
/// then config.filtersFor(label). For ICP, `seed` is the starting model when given; otherwise
/// the seed is selected by selectSeedObjects; the seed's points stay in the model. No objects
/// give an empty model, no stages and a warning; for ICP a single object is its own model (with
/// a warning). `progress`, when set, is called
/// with (objects aligned, objects to align) during ICP.
ClassModel buildClassModel(const std::string& label, const std::vector<ModelCloud>& objects,
                           const ModelBuildConfig& config, const ModelCloud* seed = nullptr,
                           const std::function<void(std::size_t, std::size_t)>& progress = {});

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
  std::vector<ClassModelSummary> classes;  ///< in class name order
  std::vector<std::string> warnings;       ///< about the run as a whole
  std::vector<std::string> cleared;  ///< what dead runs had left and was cleared
};

/// Builds the model of every class (or of options.classes) of the objects folder `objects`
/// (see listObjectFiles) into the folder `out`:
///   - `out/<Class>.pcd`: the filtered model, binary PCD with fields x y z (writeModelPcd);
///   - `out/raw/<Class>.pcd`: the concatenation before filtering;
///   - `out/mesh/<Class>.ply`: with options.mesh, the filtered model's mesh (triangulate);
///   - `out/models.json`: per class the objects used and kept, the ICP seed and verdicts, the
///     points after each stage, the filter parameters used and the seconds taken, plus the
///     method and ICP parameters of the run.
/// A requested class without objects, or whose filtered model is empty, is reported in the
/// summary and models.json and gets no files.
///
/// `out` is an OutputFolder: locked, built in a hidden sibling and renamed into place at the
/// end, so a failure or a signal leaves `out` as it was. Throws std::invalid_argument for a bad config, and
/// std::runtime_error (naming the file or folder) for a missing objects folder, a folder
/// without object PCDs, an unreadable object or seed PCD, a seed for a class not built, no
/// class with objects among those requested, an `out` that may not be replaced (see
/// checkOutputFolder), and write failures.
BuildModelsSummary buildModels(const std::filesystem::path& objects,
                               const std::filesystem::path& out, const ModelBuildConfig& config,
                               const BuildModelsOptions& options = {});

}  // namespace granular
