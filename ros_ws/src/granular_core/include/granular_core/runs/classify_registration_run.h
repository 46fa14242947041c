#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "granular_core/registration/criteria.h"
#include "granular_core/registration/registration_classifier.h"

namespace granular {

/// One object of an objects folder and its classification.
struct ObjectRecord {
  std::string file;        ///< file name in the objects folder
  std::string true_label;  ///< the name's prefix before the first '-'; empty if none
  std::size_t points = 0;       ///< finite points in the file
  std::size_t points_used = 0;  ///< of which registered (source_min_z, source_max_points)
  std::vector<PairResult> per_model;  ///< in the order of ClassificationRun::models
  Predictions predictions;
};

/// How one criterion did over a run.
struct CriterionSummary {
  std::size_t predicted = 0;  ///< objects with a prediction
  std::size_t missing = 0;    ///< objects without one
  std::size_t labelled = 0;   ///< predicted objects with a true label
  std::size_t correct = 0;    ///< predicted objects whose prediction is their true label
  /// correct / labelled, or 0 without labelled predictions.
  double accuracy() const;
};

/// A classified objects folder.
struct ClassificationRun {
  RegistrationMethod method = RegistrationMethod::kIcp;
  std::string preset;  ///< the name the config came under, for the record
  RegistrationClassifierConfig config;
  std::vector<std::string> models;  ///< model labels
  double seconds = 0.0;  ///< wall time of preparing the models and registering the objects
  int threads = 0;       ///< threads used (RegisterOptions::threads, 0 resolved)
  std::vector<ObjectRecord> objects;  ///< in file-name order
  std::vector<std::string> warnings;

  /// Criterion 1, 2 or 3 over all objects.
  CriterionSummary summary(int criterion) const;
  /// What ran, and how each criterion did, on `out`.
  void report(std::ostream& out) const;
};

/// How classifyFolder runs, apart from the tunables.
struct ClassifyFolderOptions {
  std::string preset;        ///< recorded in the result only
  RegisterOptions registration;
  /// Called with each warning when it is found; may be empty.
  std::function<void(const std::string&)> warn;
};

/// Classifies every object PCD of `objects` (`<Label>-<stamp>-<index>.pcd`, see
/// listObjectFiles; a PCD whose name has no label is classified with an empty true label)
/// against the models of `models` (readClassModels) with `method` and `config`.
///
/// Warnings (also in the result): objects of classes without a model (they are predicted among
/// the models there are, so they count as wrong), and objects that look box-centred as a
/// whole. Throws std::invalid_argument for a bad config and std::runtime_error (naming the
/// folder or file) for a missing folder, a folder without PCDs, an unreadable PCD or models in
/// another frame.
ClassificationRun classifyFolder(const std::filesystem::path& models,
                                 const std::filesystem::path& objects, RegistrationMethod method,
                                 const RegistrationClassifierConfig& config,
                                 const ClassifyFolderOptions& options = {});

/// What writeClassificationJson writes beyond the fitness, state and predictions.
struct ClassificationJsonOptions {
  /// Each pair's final transform: 16 of the 21 numbers a pair writes, so about two thirds of
  /// the file and of the time to write it (0.27 s for the demo's 2,916 objects x 7 models).
  bool transforms = false;
};

/// Writes `run` as JSON to `file`, under a temporary name in the same folder renamed to `file`
/// at the end:
///   {"method", "preset", "parameters": {...}, "models": [...],
///    "inlier_radii": [kInlierRadii, m], "seconds", "threads",
///    "objects": [{"file", "true_label", "points", "points_used",
///                 "per_model": {"<Class>": {"fitness", "converged", "state", "iterations",
///                                          "inlier_shares": [one per radius] (with a fitness),
///                                          "transform": [16 numbers, row-major] (when asked)}},
///                 "predictions": {"criterion1": "<Class>"|null, "criterion2", "criterion3"}}],
///    "missing": {"criterion1": n, ...},
///    "accuracy": {"criterion1": {"predicted", "labelled", "correct", "accuracy"}, ...},
///    "warnings": [...]}
/// A registration that did not run has fitness and transform null; true_label is null when the
/// name has none. Throws std::runtime_error naming the file on failure.
void writeClassificationJson(const std::filesystem::path& file, const ClassificationRun& run,
                             const ClassificationJsonOptions& options = {});

}  // namespace granular
