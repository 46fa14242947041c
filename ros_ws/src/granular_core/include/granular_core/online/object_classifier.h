#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "granular_core/registration/registration_classifier.h"
#include "granular_core/supervised/supervised_classifier.h"
#include "granular_core/point_types.h"

namespace granular {

/// The class given to one object.
struct ObjectPrediction {
  /// False when the object could not be classified (too few points for the method): `label`
  /// is then "unknown" and `score` 0.
  bool classified = false;
  std::string label = "unknown";
  /// In [0, 1], how clearly the label won. Registration: 1 - best fitness / second best fitness
  /// among the models the criterion considered (0: a tie). kNN: the share of the k neighbours
  /// that voted for the label. nu-SVMs: 1 (OpenCV gives no calibrated probability).
  double score = 0.0;
};

/// Any of granular's classifiers behind one interface, for classifying objects as they come
/// (the online node): a registration method against class models, or a trained supervised
/// classifier. Registration predicts by the report's criterion 2 and, for an object that
/// converged to no model, by criterion 3, so that every object big enough gets a label.
class ObjectClassifier {
 public:
  /// Registration against the class models of a models folder (readClassModels). Throws
  /// std::runtime_error naming the folder or file when the models cannot be read, and
  /// std::invalid_argument for a bad config.
  static ObjectClassifier registration(RegistrationMethod method,
                                       const RegistrationClassifierConfig& config,
                                       const std::filesystem::path& models, int threads = 1);
  /// A supervised classifier file (SupervisedClassifier::load). Throws std::invalid_argument
  /// for svm_fitness, whose features are registration results of every model (fitness()).
  static ObjectClassifier supervised(const std::filesystem::path& file, int threads = 1);
  /// svm_fitness: a file of train_classifier --method svm_fitness, and the models folder it
  /// learnt from. Each object is registered against every model with each of the file's
  /// registration methods, under the parameters `preset` gives for the preset its features
  /// name (e.g. "tuned"), then the SVM decides from the fitness: what classify_supervised
  /// --registration decides from classify_registration's results of the same objects. Throws
  /// std::invalid_argument when the file is not svm_fitness, or the models or a preset's
  /// parameters are not those it learnt from; std::runtime_error when a file cannot be read.
  static ObjectClassifier fitness(
      const std::filesystem::path& file, const std::filesystem::path& models,
      const std::function<RegistrationClassifierConfig(const std::string&)>& preset,
      int threads = 1);

  ObjectClassifier(ObjectClassifier&&) noexcept;
  ObjectClassifier& operator=(ObjectClassifier&&) noexcept;
  ~ObjectClassifier();

  /// "icp", "ndt", "svm", ...
  std::string method() const;
  /// The classes it can answer.
  std::vector<std::string> labels() const;
  /// Warnings from preparing it (e.g. an NDT model without cells).
  const std::vector<std::string>& warnings() const;

  /// One prediction per object (object-frame clouds, see OrientedBox).
  std::vector<ObjectPrediction> classify(const std::vector<Cloud>& objects) const;

 private:
  ObjectClassifier();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace granular
