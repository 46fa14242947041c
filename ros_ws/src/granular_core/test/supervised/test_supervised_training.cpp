// SupervisedClassifier::train (supervised_training.cpp): the nu-SVM's grid search, its sample,
// and what training refuses.
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "granular_core/supervised/supervised_classifier.h"
#include "support/two_classes.h"

namespace granular {
namespace {
using testing_support::TwoClassesTest;

TEST_F(TwoClassesTest, TheSvmGridSearchChoosesTheSameOnOneThreadAsOnSeveral) {
  SupervisedConfig config;
  std::vector<std::vector<float>> features;
  for (const Cloud& cloud : train_) {
    features.push_back(objectFeatures(cloud, FeatureKind::kPointHistograms, config.histograms));
  }
  // Many grid points tie on these separable classes: the choice among them must follow the
  // grid's order, not the order the threads finish in.
  std::vector<TrainingSummary> summaries;
  const int default_threads = omp_get_max_threads();
  for (const int threads : {1, 4}) {
    omp_set_num_threads(threads);
    TrainingSummary summary;
    SupervisedClassifier::train(SupervisedMethod::kSvm, config, features, train_labels_,
                                &summary);
    summaries.push_back(summary);
  }
  omp_set_num_threads(default_threads);
  EXPECT_EQ(summaries[0].nu, summaries[1].nu);
  EXPECT_EQ(summaries[0].gamma, summaries[1].gamma);
  EXPECT_EQ(summaries[0].cross_validation, summaries[1].cross_validation);
  EXPECT_EQ(summaries[0].grid_points, summaries[1].grid_points);
  EXPECT_EQ(summaries[0].grid_points, 58u);  // 5 nu x 8 gamma, then 2 refinements of 3 x 3
}

TEST_F(TwoClassesTest, TheSvmGridSearchOnASampleKeepsEveryClassAndTrainsOnAll) {
  SupervisedConfig config;
  std::vector<std::vector<float>> features;
  for (const Cloud& cloud : train_) {
    features.push_back(objectFeatures(cloud, FeatureKind::kPointHistograms, config.histograms));
  }
  config.svm.search_objects = 20;
  TrainingSummary summary;
  const SupervisedClassifier classifier = SupervisedClassifier::train(
      SupervisedMethod::kSvm, config, features, train_labels_, &summary);
  EXPECT_EQ(summary.search_objects, 20u);  // 10 of each class's 20
  EXPECT_EQ(summary.objects, 40u);
  for (std::size_t i = 0; i < test_.size(); ++i) {
    EXPECT_EQ(classifier.predict(classifier.features(test_[i])), test_labels_[i]) << i;
  }

  // A class of 3 among 23: its share of a 6-object sample rounds to 1, but each fold needs
  // one of it, so it keeps 2 (folds); the Cars keep their share, 5.
  std::vector<std::vector<float>> unbalanced;
  std::vector<std::string> labels;
  std::size_t vans = 0;
  for (std::size_t i = 0; i < features.size(); ++i) {
    if (train_labels_[i] == "Car" || vans++ < 3) {
      unbalanced.push_back(features[i]);
      labels.push_back(train_labels_[i]);
    }
  }
  config.svm.search_objects = 6;
  config.svm.nu = {0.05, 0.1};
  SupervisedClassifier::train(SupervisedMethod::kSvm, config, unbalanced, labels, &summary);
  EXPECT_EQ(summary.search_objects, 7u);
  EXPECT_EQ(summary.objects, 23u);
}

TEST(KnnTrainingTest, TheNeighboursVoteAsManyAsKSays) {
  // Six objects along one feature (the other five 0): A at 0, 2 and 12, B at 1, 10 and 11.
  std::vector<std::vector<float>> features;
  for (const float x : {0.0f, 1.0f, 2.0f, 10.0f, 11.0f, 12.0f}) {
    features.push_back({x, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f});
  }
  const std::vector<std::string> labels = {"A", "B", "A", "B", "B", "A"};
  SupervisedConfig config;
  config.knn.k = 1;
  TrainingSummary summary;
  const SupervisedClassifier one =
      SupervisedClassifier::train(SupervisedMethod::kKnn, config, features, labels, &summary);
  EXPECT_EQ(summary.objects, 6u);
  for (std::size_t i = 0; i < features.size(); ++i) {
    const SupervisedPrediction prediction = one.predictWithScore(features[i]);
    EXPECT_EQ(prediction.label, labels[i]) << i;  // its own training object is nearest
    EXPECT_EQ(prediction.score, 1.0) << i;
  }
  // Three neighbours of the B at 1 are the As at 0 and 2 and itself: A, two votes of three.
  config.knn.k = 3;
  const SupervisedClassifier three =
      SupervisedClassifier::train(SupervisedMethod::kKnn, config, features, labels);
  const SupervisedPrediction prediction = three.predictWithScore(features[1]);
  EXPECT_EQ(prediction.label, "A");
  EXPECT_DOUBLE_EQ(prediction.score, 2.0 / 3.0);
}

TEST_F(TwoClassesTest, TrainingRefusesOneLabelAndFeaturesOfTheWrongSize) {
  SupervisedConfig config;
  std::vector<std::vector<float>> features;
  for (const Cloud& cloud : train_) {
    features.push_back(meanStdFeatures(cloud));
  }
  EXPECT_THROW(SupervisedClassifier::train(SupervisedMethod::kKnn, config, features,
                                           std::vector<std::string>(train_.size(), "Car")),
               std::invalid_argument);
  EXPECT_THROW(SupervisedClassifier::train(SupervisedMethod::kSvm, config, features,
                                           train_labels_),
               std::invalid_argument);  // 6 values where the SVM takes 60
  EXPECT_THROW(SupervisedClassifier::train(SupervisedMethod::kSvmFitness, config, features,
                                           train_labels_),
               std::invalid_argument);  // svm_fitness without the names of its features
}

}  // namespace
}  // namespace granular
