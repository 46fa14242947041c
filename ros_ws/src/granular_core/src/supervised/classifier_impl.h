// SupervisedClassifier's state, shared by its three translation units: supervised_classifier.cpp
// (features and predictions), supervised_training.cpp (training and the grid search) and
// supervised_file.cpp (the file format). Internal to the supervised layer.
#pragma once

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "granular_core/search/inlier_shares.h"
#include "granular_core/supervised/knn_predictor.h"
#include "granular_core/supervised/rbf_svm.h"
#include "granular_core/supervised/supervised_classifier.h"

namespace granular {
namespace supervised_detail {

// Whether svm_fitness's feature names end with the point histograms' (its last values).
inline bool endsWithPointHistograms(SupervisedMethod method, const FeatureOrigin& origin,
                             const PointHistogramConfig& config) {
  const std::vector<std::string> histogram = pointHistogramFeatureNames(config);
  return featureKindOf(method) == FeatureKind::kRegistrationFitness &&
         origin.names.size() > histogram.size() &&
         std::equal(histogram.begin(), histogram.end(), origin.names.end() - histogram.size());
}

// Whether svm_fitness's features hold its registrations' inlier shares (readRegistrationFeatures
// names them with inlierShareFeatureName).
inline bool namesInlierShares(const FeatureOrigin& origin) {
  return std::any_of(origin.names.begin(), origin.names.end(), isInlierShareFeatureName);
}

}  // namespace supervised_detail

struct SupervisedClassifier::Impl {
  SupervisedMethod method = SupervisedMethod::kKnn;
  SupervisedConfig config;
  std::vector<std::string> labels;
  TrainingSummary training;
  FeatureOrigin origin;
  /// svm_fitness: whether its feature names end with the point histograms' (set with origin).
  bool point_histograms = false;
  /// svm_fitness: whether its features hold the inlier shares (set with origin).
  bool inlier_shares = false;
  /// Each feature is used as (value - offset) * scale: standardised (kNN's option: offset the
  /// training mean, scale 1 / deviation) or, for the SVM, mapped to [0, 1] over the training
  /// set (offset the minimum, scale 1 / range), as libsvm's guide advises: a histogram bin that
  /// is almost always empty in training would otherwise be blown up by a tiny deviation.
  bool standardize = false;
  std::vector<float> offset;
  std::vector<float> scale;
  cv::Ptr<cv::ml::StatModel> model;  ///< what the file keeps
  /// What answers: OpenCV's answers, computed faster; one of the two, by method.
  std::optional<KnnPredictor> knn_predictor;
  std::optional<RbfSvmPredictor> svm_predictor;

  /// The model and its predictor; false when it is no one-vs-one RBF SVM of the labels.
  bool setSvm(const cv::Ptr<cv::ml::SVM>& svm) {
    model = svm;
    svm_predictor = RbfSvmPredictor::from(*svm, static_cast<int>(labels.size()));
    return svm_predictor.has_value();
  }

  std::size_t size() const {
    return featureKindOf(method) == FeatureKind::kRegistrationFitness
               ? origin.names.size()
               : featureSize(featureKindOf(method), config.histograms);
  }

  cv::Mat prepare(const std::vector<float>& features) const {
    if (features.size() != size()) {
      throw std::invalid_argument("a feature vector of " + std::to_string(features.size()) +
                                  " values, the classifier takes " + std::to_string(size()));
    }
    cv::Mat row(1, static_cast<int>(features.size()), CV_32F);
    for (std::size_t i = 0; i < features.size(); ++i) {
      row.at<float>(static_cast<int>(i)) =
          standardize ? (features[i] - offset[i]) * scale[i] : features[i];
    }
    return row;
  }
};

}  // namespace granular
