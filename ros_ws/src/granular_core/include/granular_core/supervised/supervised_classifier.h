#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "granular_core/supervised/object_features.h"

namespace granular {

/// The supervised classifiers beside the registration ones.
enum class SupervisedMethod {
  kKnn,     ///< report 8.4: k nearest neighbours on [mean, std] of x, y, z (cv::ml::KNearest)
  kSvm,     ///< paper 001: nu-SVM, RBF kernel, on the 60 point-feature-histogram values
  kSvmEsf,  ///< the same nu-SVM on PCL's 640 ESF values
  /// the same nu-SVM on the object's registration fitness against every class model
  /// (FeatureKind::kRegistrationFitness): a learned rule in place of the lowest fitness
  kSvmFitness,
};

template <>
struct config::EnumNames<SupervisedMethod> {
  static constexpr const char* what = "method";
  static constexpr std::array<std::pair<SupervisedMethod, const char*>, 4> values{
      {{SupervisedMethod::kKnn, "knn"},
       {SupervisedMethod::kSvm, "svm"},
       {SupervisedMethod::kSvmEsf, "svm_esf"},
       {SupervisedMethod::kSvmFitness, "svm_fitness"}}};
};

/// "knn", "svm", "svm_esf" or "svm_fitness".
inline const char* supervisedMethodName(SupervisedMethod method) {
  return config::enumName(method);
}
inline std::optional<SupervisedMethod> supervisedMethodFromName(const std::string& name) {
  return config::enumFromName<SupervisedMethod>(name);
}
/// The features a method classifies.
FeatureKind featureKindOf(SupervisedMethod method);

struct KnnConfig {
  int k = 3;
  /// Scale each feature to zero mean and unit deviation over the training set first. Off by
  /// default, as the report's scikit-learn classifier ran (all six values are metres).
  bool standardize = false;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("k", self.k, config::atLeast(1, "neighbours"));
    visit("standardize", self.standardize);
  }
};

/// nu-SVM training (cv::ml::SVM, NU_SVC, RBF kernel), each feature scaled to [0, 1] over the
/// training set. nu and
/// gamma are chosen on the training set only, by a grid search with cross-validation, coarse to
/// fine as the paper does: first every nu of `nu` with gamma = 2^g for g from log2_gamma_min to
/// log2_gamma_max in steps of log2_gamma_step; then `refinements` times a finer grid (half the
/// gamma step, nu times 0.7, 1 and 1.4) around the best. (A nu-SVM has nu where a C-SVM has C;
/// the paper's "C" is nu here.) Among pairs of equal accuracy the larger nu wins.
/// With `search_objects` the search cross-validates on a stratified sample of that many
/// training objects; the chosen pair then trains on all of them.
struct SvmConfig {
  std::vector<double> nu = {0.05, 0.1, 0.2, 0.3, 0.5};
  double log2_gamma_min = -13.0;
  double log2_gamma_max = 1.0;
  double log2_gamma_step = 2.0;
  std::size_t refinements = 2;
  std::size_t folds = 2;     ///< the paper splits the training set into two halves
  std::uint32_t seed = 1;    ///< of the fold split (and of the search's sample)
  /// Objects the grid search cross-validates on, drawn per class in proportion (0: all). A
  /// nu-SVM trains in about the square of its objects, so half of them search four times faster.
  std::size_t search_objects = 0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("nu", self.nu, config::nonEmpty(config::interval(0, 1, "", true)));
    visit("log2_gamma_min", self.log2_gamma_min);
    visit("log2_gamma_max", self.log2_gamma_max);
    visit("log2_gamma_step", self.log2_gamma_step, config::positive());
    visit("refinements", self.refinements);
    visit("folds", self.folds, config::atLeast(2));
    visit("seed", self.seed);
    visit("search_objects", self.search_objects);
  }
};

/// svm_fitness's features beside the registration fitness: with `inlier_shares`, each
/// registration's inlier shares (inlier_shares.h; registrationFitnessFeatures); and the
/// object's point-feature histograms (the svm's 60 values, computed with `histograms`), each
/// scaled to [0, 1] over the training set as every SVM feature is, then multiplied by
/// `histogram_weight`, so that the shape they describe moves the RBF kernel's distances
/// without drowning the fitness values. 0: no histograms (and no objects folder needed).
struct SvmFitnessConfig {
  bool inlier_shares = true;
  double histogram_weight = 0.3;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("inlier_shares", self.inlier_shares);
    visit("histogram_weight", self.histogram_weight, config::nonNegative());
  }
};

/// Every tunable of the supervised classifiers.
struct SupervisedConfig {
  KnnConfig knn;
  SvmConfig svm;
  SvmFitnessConfig svm_fitness;
  PointHistogramConfig histograms;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("knn", self.knn);
    visit("svm", self.svm);
    visit("svm_fitness", self.svm_fitness);
    visit("histograms", self.histograms);
  }
};

/// Throws std::invalid_argument naming the field for a value out of range.
void validate(const SupervisedConfig& config);

/// What training found.
struct TrainingSummary {
  std::size_t objects = 0;
  double seconds = 0.0;            ///< the whole training, grid search included
  double nu = 0.0;                 ///< SVM: chosen
  double gamma = 0.0;              ///< SVM: chosen
  double cross_validation = 0.0;   ///< SVM: accuracy of the chosen pair across the folds
  std::size_t search_objects = 0;  ///< SVM: objects the grid search cross-validated on
  std::size_t grid_points = 0;     ///< SVM: (nu, gamma) pairs tried
};

/// Features a classifier does not compute from a cloud (svm_fitness's registration fitness):
/// the name of each value in order, and where they came from (the registration runs' methods,
/// parameters and models, as text), both kept in the classifier file so that classification
/// can refuse features computed otherwise.
struct FeatureOrigin {
  std::vector<std::string> names;
  std::string source;
};

/// A label and how clearly it won: the share of the k neighbours that voted for it (kNN), or
/// the share of its one-vs-one duels it won against the other classes (nu-SVM: OpenCV gives
/// no calibrated probability; 1 for a classifier of two classes, whose single duel decides).
struct SupervisedPrediction {
  std::string label;
  double score = 1.0;
};

/// A trained supervised classifier: its method, the configuration its features were computed
/// with, the labels, the standardisation and the OpenCV model.
class SupervisedClassifier {
 public:
  /// Trains on feature vectors (one per object, all of featureSize, or for svm_fitness of
  /// `origin.names`' size) and their labels. Throws std::invalid_argument for a bad config,
  /// mismatched sizes, no objects, a single label, or svm_fitness without feature names.
  static SupervisedClassifier train(SupervisedMethod method, const SupervisedConfig& config,
                                    const std::vector<std::vector<float>>& features,
                                    const std::vector<std::string>& labels,
                                    TrainingSummary* summary = nullptr,
                                    const FeatureOrigin& origin = {});

  /// Reads a file written by save(). Throws std::runtime_error naming the file when it cannot
  /// be read, is not a granular classifier, or its parts do not agree.
  static SupervisedClassifier load(const std::filesystem::path& file);

  SupervisedClassifier(SupervisedClassifier&&) noexcept;
  SupervisedClassifier& operator=(SupervisedClassifier&&) noexcept;
  ~SupervisedClassifier();

  /// Writes OpenCV YAML under a temporary name renamed to `file` at the end.
  void save(const std::filesystem::path& file) const;

  SupervisedMethod method() const;
  const SupervisedConfig& config() const;
  const std::vector<std::string>& labels() const;
  const TrainingSummary& training() const;
  /// svm_fitness: the names and source of its features; empty for the others.
  const FeatureOrigin& featureOrigin() const;
  /// svm_fitness: whether its features end with the object's point histograms
  /// (pointHistogramFeatureNames), which fitnessFeatures() appends.
  bool takesPointHistograms() const;
  /// svm_fitness: whether its features hold the registrations' inlier shares
  /// (registrationFitnessFeatures with inlier_shares), as its feature names say.
  bool takesInlierShares() const;
  /// svm_fitness: the feature vector of an object from its registration fitness features
  /// (registrationFitnessFeatures) and, when the classifier takes them, its cloud's point
  /// histograms (`object` in its own frame; unused otherwise).
  std::vector<float> fitnessFeatures(std::vector<float> fitness, const Cloud& object) const;

  /// The feature vector of an object, as this classifier's configuration computes it. Throws
  /// std::invalid_argument for svm_fitness, whose features come from registration.
  std::vector<float> features(const Cloud& object) const;
  /// The label of a feature vector. Thread-safe.
  std::string predict(const std::vector<float>& features) const;
  /// The label with its score. Thread-safe.
  SupervisedPrediction predictWithScore(const std::vector<float>& features) const;
  /// predictWithScore of each feature vector, the same answers in one call: kNN searches all
  /// of them in one pass over its training set (a frame's 200 objects: one pass, not 200).
  /// Thread-safe.
  std::vector<SupervisedPrediction> predictWithScores(
      const std::vector<std::vector<float>>& features) const;

 private:
  SupervisedClassifier();
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The first field in which two feature configurations differ, as "field: a vs b"; empty when
/// they agree. Only the fields the method's features depend on are compared.
std::string featureConfigDifference(SupervisedMethod method, const PointHistogramConfig& a,
                                    const PointHistogramConfig& b);

}  // namespace granular
