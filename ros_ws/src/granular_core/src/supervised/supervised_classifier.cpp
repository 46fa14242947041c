// SupervisedClassifier's features and predictions (training: supervised_training.cpp; the file
// format: supervised_file.cpp).
#include "granular_core/supervised/supervised_classifier.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "classifier_impl.h"

namespace granular {

FeatureKind featureKindOf(SupervisedMethod method) {
  switch (method) {
    case SupervisedMethod::kKnn:
      return FeatureKind::kMeanStd;
    case SupervisedMethod::kSvm:
      return FeatureKind::kPointHistograms;
    case SupervisedMethod::kSvmEsf:
      return FeatureKind::kEsf;
    case SupervisedMethod::kSvmFitness:
      return FeatureKind::kRegistrationFitness;
  }
  return FeatureKind::kMeanStd;
}

void validate(const SupervisedConfig& config) {
  config::validateFields(config);
  config::require(config.svm.log2_gamma_min <= config.svm.log2_gamma_max,
                  "svm.log2_gamma_min must be at most svm.log2_gamma_max");
}

std::string featureConfigDifference(SupervisedMethod method, const PointHistogramConfig& a,
                                    const PointHistogramConfig& b) {
  if (featureKindOf(method) != FeatureKind::kPointHistograms) {
    return "";
  }
  const config::Json first = config::toJson(a);
  const config::Json second = config::toJson(b);
  for (const auto& [key, value] : first.items()) {
    if (value != second.at(key)) {
      const auto text = [](const config::Json& json) {
        return json.is_string() ? json.get<std::string>() : json.dump();
      };
      return key + ": " + text(value) + " vs " + text(second.at(key));
    }
  }
  return "";
}

SupervisedClassifier::SupervisedClassifier() : impl_(std::make_unique<Impl>()) {}
SupervisedClassifier::SupervisedClassifier(SupervisedClassifier&&) noexcept = default;
SupervisedClassifier& SupervisedClassifier::operator=(SupervisedClassifier&&) noexcept = default;
SupervisedClassifier::~SupervisedClassifier() = default;

SupervisedMethod SupervisedClassifier::method() const { return impl_->method; }
const SupervisedConfig& SupervisedClassifier::config() const { return impl_->config; }
const std::vector<std::string>& SupervisedClassifier::labels() const { return impl_->labels; }
const TrainingSummary& SupervisedClassifier::training() const { return impl_->training; }
const FeatureOrigin& SupervisedClassifier::featureOrigin() const { return impl_->origin; }

bool SupervisedClassifier::takesPointHistograms() const { return impl_->point_histograms; }

bool SupervisedClassifier::takesInlierShares() const { return impl_->inlier_shares; }

std::vector<float> SupervisedClassifier::fitnessFeatures(std::vector<float> fitness,
                                                         const Cloud& object) const {
  if (takesPointHistograms()) {
    const std::vector<float> histogram = pointHistogramFeatures(object, impl_->config.histograms);
    fitness.insert(fitness.end(), histogram.begin(), histogram.end());
  }
  return fitness;
}

std::vector<float> SupervisedClassifier::features(const Cloud& object) const {
  return objectFeatures(object, featureKindOf(impl_->method), impl_->config.histograms);
}

std::string SupervisedClassifier::predict(const std::vector<float>& features) const {
  return predictWithScore(features).label;
}

SupervisedPrediction SupervisedClassifier::predictWithScore(
    const std::vector<float>& features) const {
  return predictWithScores({features}).front();
}

std::vector<SupervisedPrediction> SupervisedClassifier::predictWithScores(
    const std::vector<std::vector<float>>& features) const {
  std::vector<SupervisedPrediction> predictions;
  predictions.reserve(features.size());
  if (features.empty()) {
    return predictions;
  }
  cv::Mat rows(static_cast<int>(features.size()), static_cast<int>(impl_->size()), CV_32F);
  for (std::size_t r = 0; r < features.size(); ++r) {
    impl_->prepare(features[r]).copyTo(rows.row(static_cast<int>(r)));
  }
  const auto add = [&](long index, double score) {
    if (index < 0 || index >= static_cast<long>(impl_->labels.size())) {
      throw std::runtime_error("the classifier answered an unknown class " +
                               std::to_string(index));
    }
    predictions.push_back({impl_->labels[static_cast<std::size_t>(index)], score});
  };
  if (impl_->knn_predictor) {
    // The score: the share of the neighbours that voted for the answer.
    const double neighbours = impl_->knn_predictor->neighbours();
    for (const KnnPredictor::Answer& answer : impl_->knn_predictor->predict(rows)) {
      add(std::lround(answer.response), answer.votes / neighbours);
    }
  } else {
    // The score: the share of its one-vs-one duels the answer won.
    const double duels = static_cast<double>(impl_->labels.size() - 1);
    for (const RbfSvmPredictor::Answer& answer : impl_->svm_predictor->predict(rows)) {
      add(answer.label, answer.votes / duels);
    }
  }
  return predictions;
}

}  // namespace granular
