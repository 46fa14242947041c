// The classifier file (supervised_file.cpp): a saved classifier loads as it was, and a file
// that is not one, or not whole, is refused with its name.
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/supervised/supervised_classifier.h"
#include "support/two_classes.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

// The two classes, their mean/std features, and a folder for the files.
class SupervisedFileTest : public testing_support::TwoClassesTest {
 protected:
  void SetUp() override {
    TwoClassesTest::SetUp();
    std::random_device entropy;
    folder_ = fs::temp_directory_path() /
              ("granular_supervised_file_" + std::to_string(entropy()) + std::to_string(entropy()));
    fs::create_directories(folder_);
    for (const Cloud& cloud : train_) {
      features_.push_back(meanStdFeatures(cloud));
    }
    for (const Cloud& cloud : test_) {
      held_out_.push_back(meanStdFeatures(cloud));
    }
  }
  void TearDown() override { fs::remove_all(folder_); }

  static std::string read(const fs::path& file) {
    std::ifstream stream(file);
    std::stringstream content;
    content << stream.rdbuf();
    return content.str();
  }

  // The message load() throws for `file`, which must name it; empty when it loads.
  static std::string refusal(const fs::path& file) {
    try {
      SupervisedClassifier::load(file);
    } catch (const std::runtime_error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(file.string()), std::string::npos) << message;
      return message;
    }
    return "";
  }

  // A file saved from a trained kNN, then `from` replaced by `to` in its text.
  fs::path edited(const std::string& name, const std::string& from, const std::string& to) {
    const fs::path file = folder_ / name;
    SupervisedClassifier::train(SupervisedMethod::kKnn, SupervisedConfig(), features_,
                                train_labels_)
        .save(file);
    std::string text = read(file);
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) {
      text.replace(at, from.size(), to);
    }
    std::ofstream(file, std::ios::trunc) << text;
    return file;
  }

  fs::path folder_;
  std::vector<std::vector<float>> features_, held_out_;
};

TEST_F(SupervisedFileTest, ASavedClassifierLoadsAsItWasTrained) {
  SupervisedConfig config;
  config.svm.refinements = 0;
  config.knn.k = 5;
  const FeatureOrigin origin{{"mean_x", "mean_y", "mean_z", "std_x", "std_y", "std_z"},
                             "test: the mean/std values, named"};
  for (const SupervisedMethod method : {SupervisedMethod::kKnn, SupervisedMethod::kSvmFitness}) {
    SCOPED_TRACE(supervisedMethodName(method));
    const SupervisedClassifier trained =
        SupervisedClassifier::train(method, config, features_, train_labels_, nullptr,
                                    method == SupervisedMethod::kSvmFitness ? origin
                                                                            : FeatureOrigin());
    const fs::path file = folder_ / (std::string(supervisedMethodName(method)) + ".yml");
    trained.save(file);
    const SupervisedClassifier loaded = SupervisedClassifier::load(file);
    EXPECT_EQ(loaded.method(), method);
    EXPECT_EQ(loaded.labels(), trained.labels());
    EXPECT_EQ(loaded.config().knn.k, 5);
    EXPECT_EQ(loaded.featureOrigin().names, trained.featureOrigin().names);
    EXPECT_EQ(loaded.featureOrigin().source, trained.featureOrigin().source);
    EXPECT_EQ(loaded.training().objects, trained.training().objects);
    EXPECT_EQ(loaded.training().nu, trained.training().nu);
    EXPECT_EQ(loaded.training().gamma, trained.training().gamma);
    EXPECT_EQ(loaded.training().cross_validation, trained.training().cross_validation);
    EXPECT_EQ(loaded.training().grid_points, trained.training().grid_points);
    const std::vector<SupervisedPrediction> before = trained.predictWithScores(held_out_);
    const std::vector<SupervisedPrediction> after = loaded.predictWithScores(held_out_);
    ASSERT_EQ(after.size(), before.size());
    for (std::size_t i = 0; i < before.size(); ++i) {
      EXPECT_EQ(after[i].label, before[i].label) << i;
      EXPECT_EQ(after[i].score, before[i].score) << i;
    }
  }
}

TEST_F(SupervisedFileTest, AFileThatIsNoWholeClassifierIsRefusedWithItsName) {
  EXPECT_NE(refusal(folder_ / "missing.yml").find("no such classifier file"), std::string::npos);
  EXPECT_NE(refusal(folder_).find("is a folder"), std::string::npos);

  const fs::path other = folder_ / "other.yml";
  std::ofstream(other) << "%YAML:1.0\nformat: something_else\n";
  EXPECT_NE(refusal(other).find("not a granular classifier file"), std::string::npos);

  // Cut short in the middle of its model.
  const fs::path whole = folder_ / "whole.yml";
  SupervisedClassifier::train(SupervisedMethod::kKnn, SupervisedConfig(), features_,
                              train_labels_)
      .save(whole);
  const std::string text = read(whole);
  const fs::path cut = folder_ / "cut.yml";
  std::ofstream(cut) << text.substr(0, text.size() / 2);
  EXPECT_NE(refusal(cut), "");

  EXPECT_NE(refusal(edited("version.yml", "version: 1", "version: 2")).find("another version"),
            std::string::npos);
  EXPECT_NE(refusal(edited("size.yml", "feature_size: 6", "feature_size: 7"))
                .find("does not match its feature configuration"),
            std::string::npos);
  EXPECT_NE(refusal(edited("method.yml", "method: knn", "method: forest"))
                .find("unknown method 'forest'"),
            std::string::npos);
}

TEST_F(SupervisedFileTest, SavingIntoAMissingFolderFailsAndWritesNothing) {
  const SupervisedClassifier trained = SupervisedClassifier::train(
      SupervisedMethod::kKnn, SupervisedConfig(), features_, train_labels_);
  EXPECT_ANY_THROW(trained.save(folder_ / "absent" / "knn.yml"));
  EXPECT_FALSE(fs::exists(folder_ / "absent"));
}

}  // namespace
}  // namespace granular
