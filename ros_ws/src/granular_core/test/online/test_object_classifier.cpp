// ObjectClassifier: one interface for the online node.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/dataset/object_names.h"
#include "granular_core/dataset/pcd_io.h"
#include "granular_core/online/object_classifier.h"
#include "granular_core/runs/classify_registration_run.h"
#include "granular_core/runs/classify_supervised_run.h"
#include "granular_core/supervised/object_features.h"
#include "granular_core/supervised/supervised_classifier.h"
#include "support/registration_scene.h"

namespace granular {
namespace {
using testing_support::ClassifyFolderTest;
namespace fs = std::filesystem;

TEST_F(ClassifyFolderTest, ObjectClassifierLabelsEveryObjectAndLeavesTinyOnesUnknown) {
  const ObjectClassifier classifier = ObjectClassifier::registration(
      RegistrationMethod::kIcp, converging(), root_ / "models");
  EXPECT_EQ(classifier.method(), "icp");
  EXPECT_EQ(classifier.labels(), (std::vector<std::string>{"Long", "Tall"}));
  std::vector<Cloud> objects;
  for (const ModelCloud& object : objects_) {
    Cloud cloud;
    for (const pcl::PointXYZ& p : object.points) {
      cloud.push_back(PointXYZIT(p.x, p.y, p.z, 0, 0.0));
    }
    objects.push_back(cloud);
  }
  objects.push_back(Cloud());  // nothing to register
  const std::vector<ObjectPrediction> predictions = classifier.classify(objects);
  ASSERT_EQ(predictions.size(), objects.size());
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    EXPECT_TRUE(predictions[i].classified) << i;
    EXPECT_EQ(predictions[i].label, models_[truth_[i]].label) << i;
    // The right model fits far better than the other one.
    EXPECT_GT(predictions[i].score, 0.5) << i;
    EXPECT_LE(predictions[i].score, 1.0) << i;
  }
  EXPECT_FALSE(predictions.back().classified);
  EXPECT_EQ(predictions.back().label, "unknown");
  EXPECT_THROW(ObjectClassifier::registration(RegistrationMethod::kIcp, converging(),
                                              root_ / "no_models"),
               std::runtime_error);
}

// The supervised path computes a frame's features over the node's threads: the same answers.
TEST_F(ClassifyFolderTest, SupervisedAnswersTheSameOnOneThreadAsOnSeveral) {
  std::vector<Cloud> objects;
  std::vector<std::vector<float>> features;
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    Cloud& cloud = objects.emplace_back();
    for (const pcl::PointXYZ& p : objects_[i].points) {
      cloud.push_back(PointXYZIT(p.x, p.y, p.z, 0, 0.0));
    }
    features.push_back(objectFeatures(cloud, FeatureKind::kPointHistograms));
    labels.push_back(models_[truth_[i]].label);
  }
  const fs::path model = root_ / "svm.yml";
  SupervisedClassifier::train(SupervisedMethod::kSvm, SupervisedConfig(), features, labels)
      .save(model);
  objects.push_back(Cloud());  // nothing to classify: unknown
  const std::vector<ObjectPrediction> one =
      ObjectClassifier::supervised(model, 1).classify(objects);
  const std::vector<ObjectPrediction> three =
      ObjectClassifier::supervised(model, 3).classify(objects);
  ASSERT_EQ(one.size(), objects.size());
  ASSERT_EQ(three.size(), objects.size());
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    EXPECT_EQ(one[i].label, labels[i]) << i;
    EXPECT_EQ(three[i].label, labels[i]) << i;
  }
  EXPECT_FALSE(one.back().classified);
  EXPECT_FALSE(three.back().classified);
}

// The online classifier registers each object itself and must answer as the offline results do.
TEST_F(ClassifyFolderTest, OnlineSvmFitnessAnswersAsTheOfflineResults) {
  // Each view whole ("Dense", 300 points) and thinned to every tenth point ("Sparse"): both fit
  // their model alike, so only the point count tells the classes apart, and the online
  // features must count the points as the results files do.
  fs::create_directories(root_ / "density");
  std::vector<ModelCloud> views;
  std::vector<std::string> labels;
  for (const ModelCloud& object : objects_) {
    ModelCloud sparse;
    for (std::size_t p = 0; p < object.size(); p += 10) {
      sparse.push_back(object.points[p]);
    }
    for (const auto& [view, label] : {std::pair(object, "Dense"), std::pair(sparse, "Sparse")}) {
      writeModelPcd(root_ / "density" / (std::string(label) + "-" +
                                         std::to_string(100 + views.size()) + "-1.pcd"),
                    view);
      views.push_back(view);
      labels.push_back(label);
    }
  }
  ClassifyFolderOptions options;
  options.preset = "converging";
  std::vector<fs::path> results;
  for (const RegistrationMethod method : {RegistrationMethod::kIcp, RegistrationMethod::kNdt}) {
    results.push_back(root_ / (std::string(registrationMethodName(method)) + ".json"));
    writeClassificationJson(
        results.back(),
        classifyFolder(root_ / "models", root_ / "density", method, converging(), options));
  }
  // With the objects' point histograms (the default), which the node computes itself.
  SupervisedConfig config;
  config.svm.refinements = 0;
  const fs::path model = root_ / "svm_fitness.yml";
  trainOnRegistration(results, config, root_ / "density").classifier.save(model);
  ASSERT_TRUE(SupervisedClassifier::load(model).takesPointHistograms());
  const SupervisedRun offline =
      classifyRegistrationResults(SupervisedClassifier::load(model), results, root_ / "density");

  std::vector<std::string> presets_asked;
  const ObjectClassifier online = ObjectClassifier::fitness(
      model, root_ / "models", [&](const std::string& preset) {
        presets_asked.push_back(preset);
        return converging();
      });
  EXPECT_EQ(presets_asked, (std::vector<std::string>{"converging", "converging"}));
  EXPECT_EQ(online.method(), "svm_fitness");
  // The views in the offline run's (file name) order: "<Label>-<100 + i>-1.pcd" is views[i].
  std::vector<Cloud> objects;
  for (const std::string& file : offline.files) {
    const std::size_t i = std::stoul(file.substr(file.find('-') + 1)) - 100;
    EXPECT_EQ(objectClass(file), labels.at(i));
    Cloud cloud;
    for (const pcl::PointXYZ& p : views.at(i).points) {
      cloud.push_back(PointXYZIT(p.x, p.y, p.z, 0, 0.0));
    }
    objects.push_back(cloud);
  }
  objects.push_back(Cloud());  // nothing to register: unknown
  const std::vector<ObjectPrediction> predictions = online.classify(objects);
  ASSERT_EQ(predictions.size(), offline.files.size() + 1);
  for (std::size_t k = 0; k < offline.files.size(); ++k) {
    EXPECT_TRUE(predictions[k].classified) << offline.files[k];
    EXPECT_EQ(predictions[k].label, offline.predicted[k]) << offline.files[k];
    EXPECT_EQ(predictions[k].label, offline.true_labels[k]) << offline.files[k];
  }
  EXPECT_FALSE(predictions.back().classified);

  // Other parameters than it learnt from, or the file taken for a plain supervised one.
  RegistrationClassifierConfig other = converging();
  other.icp.max_iterations = 31;
  try {
    ObjectClassifier::fitness(model, root_ / "models", [&](const std::string&) { return other; });
    ADD_FAILURE() << "other ICP parameters were accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("preset 'converging' gives"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(ObjectClassifier::supervised(model), std::invalid_argument);
}

}  // namespace
}  // namespace granular
