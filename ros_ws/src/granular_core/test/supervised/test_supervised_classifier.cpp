// kNN and the nu-SVMs: each classifies held-out objects, alone and together, after saving
// and loading too; a bad config is refused.
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/supervised/supervised_classifier.h"
#include "support/two_classes.h"

namespace granular {
namespace {

namespace fs = std::filesystem;
using testing_support::TwoClassesTest;

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

TEST(SupervisedConfigTest, ABadConfigIsRefusedAndADifferentFeatureConfigNamed) {
  SupervisedConfig config;
  config.histograms.bins = 0;
  EXPECT_THROW(validate(config), std::invalid_argument);

  PointHistogramConfig other;
  other.bins = 9;
  EXPECT_EQ(featureConfigDifference(SupervisedMethod::kSvm, PointHistogramConfig(), other),
            "bins: 7 vs 9");
  EXPECT_EQ(featureConfigDifference(SupervisedMethod::kKnn, PointHistogramConfig(), other), "");
}

}  // namespace
}  // namespace granular
