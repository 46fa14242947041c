// kNN and the nu-SVMs: train, classify, save and load, refuse bad input.
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <omp.h>

#include "granular_core/supervised/supervised_classifier.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

// Two well separated synthetic classes: boxes 4.5 m long, 1.5 m high and boxes 2 m long, 2.5 m
// high, seen from a random side, with a little noise.
class TwoClassesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 random(3);
    std::normal_distribution<float> noise(0.0f, 0.02f);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    for (int i = 0; i < 60; ++i) {
      const bool car = i % 2 == 0;
      const float length = car ? 4.5f : 2.0f, height = car ? 1.5f : 2.5f;
      Cloud cloud;
      for (int p = 0; p < 300; ++p) {
        // The left side and the front.
        const bool side = unit(random) < 0.7f;
        const float x = side ? (unit(random) - 0.5f) * length : length / 2;
        const float y = side ? 0.9f : (unit(random) - 0.5f) * 1.8f;
        cloud.push_back(PointXYZIT(x + noise(random), y + noise(random),
                                   unit(random) * height, car ? 200 : 50, 0.0));
      }
      (i < 40 ? train_ : test_).push_back(cloud);
      (i < 40 ? train_labels_ : test_labels_).push_back(car ? "Car" : "Van");
    }
  }

  std::vector<Cloud> train_, test_;
  std::vector<std::string> train_labels_, test_labels_;
};

TEST_F(TwoClassesTest, EveryMethodClassifiesHeldOutObjectsAndSurvivesSaveAndLoad) {
  SupervisedConfig config;
  config.svm.refinements = 1;
  const fs::path folder = fs::temp_directory_path() /
                          ("granular_supervised_" + std::to_string(std::random_device()()));
  fs::create_directories(folder);
  for (const SupervisedMethod method :
       {SupervisedMethod::kKnn, SupervisedMethod::kSvm, SupervisedMethod::kSvmEsf}) {
    std::vector<std::vector<float>> features;
    for (const Cloud& cloud : train_) {
      features.push_back(objectFeatures(cloud, featureKindOf(method), config.histograms));
    }
    TrainingSummary summary;
    const SupervisedClassifier classifier =
        SupervisedClassifier::train(method, config, features, train_labels_, &summary);
    EXPECT_EQ(classifier.labels(), (std::vector<std::string>{"Car", "Van"}));
    EXPECT_EQ(summary.objects, train_.size());
    const fs::path file = folder / (std::string(supervisedMethodName(method)) + ".yml");
    classifier.save(file);
    const SupervisedClassifier loaded = SupervisedClassifier::load(file);
    EXPECT_EQ(loaded.method(), method);
    std::vector<std::vector<float>> all;
    for (std::size_t i = 0; i < test_.size(); ++i) {
      const std::vector<float> f = classifier.features(test_[i]);
      EXPECT_EQ(classifier.predict(f), test_labels_[i]) << supervisedMethodName(method) << i;
      EXPECT_EQ(loaded.predict(loaded.features(test_[i])), classifier.predict(f))
          << supervisedMethodName(method) << " after loading, object " << i;
      all.push_back(f);
    }
    // All the held-out objects (both classes) in one call answer as each alone, scores too.
    const std::vector<SupervisedPrediction> together = classifier.predictWithScores(all);
    ASSERT_EQ(together.size(), all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
      const SupervisedPrediction alone = classifier.predictWithScore(all[i]);
      EXPECT_EQ(together[i].label, alone.label) << supervisedMethodName(method) << i;
      EXPECT_EQ(together[i].score, alone.score) << supervisedMethodName(method) << i;
    }
    EXPECT_TRUE(classifier.predictWithScores({}).empty());
  }
  fs::remove_all(folder);
}

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

TEST_F(TwoClassesTest, BadInputIsRefusedWithAClearMessage) {
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
  config.histograms.bins = 0;
  EXPECT_THROW(validate(config), std::invalid_argument);

  PointHistogramConfig other;
  other.bins = 9;
  EXPECT_EQ(featureConfigDifference(SupervisedMethod::kSvm, PointHistogramConfig(), other),
            "bins: 7 vs 9");
  EXPECT_EQ(featureConfigDifference(SupervisedMethod::kKnn, PointHistogramConfig(), other), "");

  const fs::path file = fs::temp_directory_path() /
                        ("granular_not_a_model_" + std::to_string(std::random_device()()) + ".yml");
  std::ofstream(file) << "%YAML:1.0\nformat: something_else\n";
  try {
    SupervisedClassifier::load(file);
    ADD_FAILURE() << "loaded a file that is not a classifier";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(file.string()), std::string::npos);
  }
  fs::remove(file);
}

}  // namespace
}  // namespace granular
