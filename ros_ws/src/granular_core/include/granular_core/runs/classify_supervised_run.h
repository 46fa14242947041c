#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "granular_core/supervised/supervised_classifier.h"

namespace granular {

/// The objects of an objects folder and their feature vectors.
struct FolderFeatures {
  std::vector<std::string> files;    ///< file names, in name order
  std::vector<std::string> labels;   ///< true label from each name (empty if none)
  std::vector<std::size_t> points;   ///< finite points of each object
  std::vector<std::vector<float>> features;
  /// Per object, microseconds to compute its features, on one core.
  std::vector<double> microseconds;
};

/// Reads every object PCD of `folder` (see listObjectFiles) and computes its features of
/// `kind`, objects spread over `threads` (0: every core). `progress` is called with (objects
/// done, objects) from one thread at a time. Throws std::runtime_error naming the folder or file
/// for a missing folder, a folder without object PCDs or an unreadable PCD.
FolderFeatures computeFolderFeatures(
    const std::filesystem::path& folder, FeatureKind kind, const PointHistogramConfig& config,
    int threads = 0, const std::function<void(std::size_t, std::size_t)>& progress = {});

/// A classified objects folder.
struct SupervisedRun {
  SupervisedMethod method = SupervisedMethod::kKnn;
  std::vector<std::string> files;
  std::vector<std::string> true_labels;
  std::vector<std::size_t> points;
  std::vector<std::string> predicted;
  double seconds = 0.0;                 ///< wall time of features and predictions
  double microseconds_per_object = 0.0; ///< features plus prediction, mean on one core
  /// svm_fitness: the wall time of the registrations its features came from (their results
  /// files' own), on top of `seconds`; 0 for the others.
  double registration_seconds = 0.0;
  std::vector<std::string> warnings;

  /// Objects, seconds, microseconds per object and accuracy, on `out`.
  void report(std::ostream& out) const;
};

/// Classifies every object of `folder` with `classifier`. Warnings: objects of classes the
/// classifier was not trained on (they count as wrong) and objects of fewer than 3 points (their
/// features are defined, from the points there are, and they are classified all the same).
SupervisedRun classifyFolderSupervised(
    const SupervisedClassifier& classifier, const std::filesystem::path& folder, int threads = 0,
    const std::function<void(std::size_t, std::size_t)>& progress = {});

/// A classifier trained on an objects folder.
struct TrainingRun {
  SupervisedClassifier classifier;
  TrainingSummary summary;

  /// What was trained, on how many objects, and for the SVMs the chosen nu and gamma, on `out`.
  void report(std::ostream& out) const;
};

/// Computes the features of every object of `folder` (computeFolderFeatures) and trains a
/// classifier of `method` on them (SupervisedClassifier::train); on the objects of `classes`
/// only when it is not empty (throws std::runtime_error naming a class without objects).
TrainingRun trainOnFolder(const std::filesystem::path& folder, SupervisedMethod method,
                          const SupervisedConfig& config, int threads = 0,
                          const std::function<void(std::size_t, std::size_t)>& progress = {},
                          const std::vector<std::string>& classes = {});

/// svm_fitness's features of an objects folder, read from classify_registration's results
/// files of it (one per registration method, each listing every object's fitness against
/// every model): per object registrationFitnessFeatures over the files in the order given.
struct RegistrationFeatures {
  FolderFeatures folder;  ///< microseconds: reading and building each object's features
  /// Names "<method>/<preset>:<Model>", "log_points" and with inlier shares
  /// "<method>/<preset>:<Model>:within_<radius>m"; the source: per file its method,
  /// preset, parameters and models (the preset's name is not compared, its parameters are).
  FeatureOrigin origin;
  double registration_seconds = 0.0;  ///< the files' own registration times, summed
};

/// Reads classify_registration results files (writeClassificationJson) of one objects folder,
/// with each pair's inlier shares among the features when `inlier_shares`. Throws
/// std::runtime_error naming the file when one cannot be read, is not such a file, has no
/// objects, lists other objects (or in another order) than the first, or has no inlier shares
/// that are asked for.
RegistrationFeatures readRegistrationFeatures(const std::vector<std::filesystem::path>& results,
                                              bool inlier_shares);

/// Trains svm_fitness on the registration results of a training objects folder; with
/// config.svm_fitness.histogram_weight above 0 also on the point histograms of its objects,
/// read from `objects` (that folder) over `threads` (0: every core); on the objects of
/// `classes` only when it is not empty. Throws std::invalid_argument when the histograms are
/// asked for and `objects` is empty, std::runtime_error naming a class without objects.
TrainingRun trainOnRegistration(const std::vector<std::filesystem::path>& results,
                                const SupervisedConfig& config,
                                const std::filesystem::path& objects = {}, int threads = 0,
                                const std::vector<std::string>& classes = {});

/// Classifies the objects of registration results files with an svm_fitness `classifier`
/// (and, when it takes point histograms, their PCDs in `objects`). Throws std::runtime_error
/// when the files do not come from the methods, parameters and models (in the same order) the
/// classifier was trained on, std::invalid_argument when the classifier takes histograms and
/// `objects` is empty. Warnings as classifyFolderSupervised.
SupervisedRun classifyRegistrationResults(const SupervisedClassifier& classifier,
                                          const std::vector<std::filesystem::path>& results,
                                          const std::filesystem::path& objects = {},
                                          int threads = 0);

/// What stops `method` from learning from what was given: an objects folder (`objects`) and
/// registration results (`registration`), as `config` asks for them. The message to show, or
/// empty when nothing does.
std::string trainingInputsProblem(SupervisedMethod method, const SupervisedConfig& config,
                                  bool objects, bool registration);

/// What stops `classifier` (read from the file `model`) from classifying what was given: the
/// feature settings of `expected` (read from the file `expected_file`; none: the model's own),
/// an objects folder (`objects`) and registration results (`registration`) that its method does
/// not take. The message to show, or empty when nothing does.
std::string supervisedInputsProblem(const SupervisedClassifier& classifier,
                                    const std::string& model, const SupervisedConfig* expected,
                                    const std::string& expected_file, bool objects,
                                    bool registration);

/// Writes `run` as JSON, the records make_report reads:
///   {"method", "primary": "label", "labels": [...], "seconds", "seconds_to_train",
///    "microseconds_per_object", "registration_seconds", "training": {...},
///    "objects": [{"file", "true_label", "points", "predictions": {"label": "<Class>"}}],
///    "accuracy", "warnings"}
/// under a temporary name renamed to `file`. Throws std::runtime_error naming the file.
void writeSupervisedJson(const std::filesystem::path& file, const SupervisedRun& run,
                         const SupervisedClassifier& classifier);

}  // namespace granular
