#pragma once

#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace granular {

/// The results file of classify_registration, as it lies on disk:
///   {"method", "preset", "parameters": {...}, "models": [...],
///    "inlier_radii": [m, ...], "seconds", "threads",
///    "objects": [{"file", "true_label", "points", "points_used",
///                 "per_model": {"<Class>": {"fitness", "converged", "state", "iterations",
///                                          "inlier_shares": [one per radius] (with a fitness),
///                                          "rejected": true (only when it was),
///                                          "transform": [16 numbers, row-major] (when asked)}},
///                 "predictions": {"criterion1": "<Class>"|null, "criterion2", "criterion3"}}],
///    "missing": {"criterion1": n, ...},
///    "accuracy": {"criterion1": {"predicted", "labelled", "correct", "accuracy"}, ...},
///    "warnings": [...]}
/// The registration layer fills it (runs/classify_registration_run) and svm_fitness reads it
/// (runs/classify_supervised_run); this unit only knows the layout.

/// One object registered against one class model.
struct RegistrationPairRecord {
  /// m^2; none when the registration did not run or its fitness was rejected (null).
  std::optional<double> fitness;
  bool converged = false;
  std::string state;  ///< registrationStateName
  int iterations = 0;
  /// Per inlier radius, with a fitness (empty without; files older than the shares have none).
  std::vector<float> inlier_shares;
  bool rejected = false;  ///< the fitness was rejected early (--early-rejection)
  /// Object frame to model frame, row-major, when the file holds transforms; none (null) when
  /// the registration did not run.
  std::optional<std::array<float, 16>> transform;
};

/// One object and its registration against every model.
struct RegistrationObjectRecord {
  std::string file;                      ///< its file name in the objects folder
  std::optional<std::string> true_label; ///< none when the name has no label
  std::size_t points = 0;
  std::size_t points_used = 0;
  std::vector<RegistrationPairRecord> per_model;  ///< in the order of the file's models
  /// The model predicted by criterion 1, 2 and 3, or none.
  std::array<std::optional<std::string>, 3> predictions;
};

/// How one criterion did over the objects.
struct RegistrationCriterionRecord {
  std::size_t predicted = 0;
  std::size_t missing = 0;
  std::size_t labelled = 0;
  std::size_t correct = 0;
  double accuracy = 0.0;
};

struct RegistrationResultsFile {
  std::string method;
  std::string preset;      ///< empty in files that have none
  std::string parameters;  ///< the "parameters" object, as compact JSON text (keys sorted)
  std::vector<std::string> models;
  /// m; none in files older than the inlier shares.
  std::optional<std::vector<double>> inlier_radii;
  double seconds = 0.0;
  int threads = 0;
  /// Each pair holds its transform ("transform" keys written and read).
  bool transforms = false;
  std::vector<RegistrationObjectRecord> objects;
  std::array<RegistrationCriterionRecord, 3> criteria;  ///< criterion 1, 2, 3
  std::vector<std::string> warnings;
};

/// Writes `results` to `file` under a temporary name renamed to `file` at the end (nothing
/// half written); the numbers read back to the same values. Throws std::runtime_error naming
/// the file on failure, std::invalid_argument when an object's per_model does not match the
/// models or `parameters` is not a JSON object.
void writeRegistrationResults(const std::filesystem::path& file,
                              const RegistrationResultsFile& results);

/// Reads a file writeRegistrationResults wrote (or an older one, without inlier_radii, preset,
/// seconds or threads). Throws std::runtime_error naming the file: "cannot read it", or "not a
/// classify_registration results file (...)" saying what is missing or malformed.
RegistrationResultsFile readRegistrationResults(const std::filesystem::path& file);

}  // namespace granular
