// classifyFolder and its JSON records.
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "granular_core/dataset/pcd_io.h"
#include "granular_core/runs/classify_registration_run.h"
#include "support/model_clouds.h"
#include "support/registration_scene.h"

namespace granular {
namespace {
using testing_clouds::shifted;
using testing_support::ClassifyFolderTest;
using testing_support::RegistrationTest;

namespace fs = std::filesystem;

TEST_F(ClassifyFolderTest, ClassifiesEveryObjectAndWritesItsRecord) {
  const ClassificationRun run =
      classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kIcp, converging());
  EXPECT_EQ(run.models, (std::vector<std::string>{"Long", "Tall"}));
  ASSERT_EQ(run.objects.size(), objects_.size());
  EXPECT_EQ(run.summary(2).correct, objects_.size());
  EXPECT_EQ(run.summary(3).correct, objects_.size());
  writeClassificationJson(root_ / "icp.json", run);
  std::ifstream stream(root_ / "icp.json");
  const nlohmann::json json = nlohmann::json::parse(stream);
  EXPECT_EQ(json["method"], "icp");
  EXPECT_EQ(json["objects"].size(), objects_.size());
  const nlohmann::json& first = json["objects"][0];
  EXPECT_EQ(first["true_label"], first["predictions"]["criterion2"]);
  EXPECT_FALSE(first["per_model"]["Long"].contains("transform"));  // only when asked
  EXPECT_TRUE(first["per_model"]["Tall"].contains("fitness"));
  EXPECT_EQ(json["accuracy"]["criterion2"]["accuracy"], 1.0);
  EXPECT_EQ(json["missing"]["criterion2"], 0);

  // Asked for, each pair's transform: the object moved onto the model it belongs to stays
  // where it is (the views are cut from the models in place), so near the identity.
  ClassificationJsonOptions with_transforms;
  with_transforms.transforms = true;
  writeClassificationJson(root_ / "icp_transforms.json", run, with_transforms);
  std::ifstream again(root_ / "icp_transforms.json");
  const nlohmann::json full = nlohmann::json::parse(again);
  const nlohmann::json& record = full["objects"][0];
  const nlohmann::json& transform = record["per_model"][record["true_label"].get<std::string>()]["transform"];
  ASSERT_EQ(transform.size(), 16u);
  for (int k = 0; k < 16; ++k) {
    EXPECT_NEAR(transform[k].get<double>(), k % 5 == 0 ? 1.0 : 0.0, 0.05) << k;
  }
  EXPECT_EQ(full["objects"][0]["per_model"]["Tall"]["fitness"], first["per_model"]["Tall"]["fitness"]);
}

TEST_F(ClassifyFolderTest, EarlyRejectionWritesTheSamePredictionsAndMarksWhatItSkipped) {
  // Two more models, so that an object has models that are neither its best nor its second.
  std::mt19937 random(4);
  writeModelPcd(root_ / "models" / "Small.pcd",
                testing_clouds::boxSurface({1.0, 0.8, 1.0}, 2000, random));
  writeModelPcd(root_ / "models" / "Huge.pcd",
                testing_clouds::boxSurface({10.0, 2.5, 3.0}, 6000, random));
  const ClassificationRun full =
      classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kNdt, converging());
  ClassifyFolderOptions early;
  early.registration.early_rejection = true;
  const ClassificationRun fast = classifyFolder(root_ / "models", root_ / "objects",
                                                RegistrationMethod::kNdt, converging(), early);
  writeClassificationJson(root_ / "full.json", full);
  writeClassificationJson(root_ / "fast.json", fast);
  std::ifstream full_stream(root_ / "full.json");
  std::ifstream fast_stream(root_ / "fast.json");
  const nlohmann::json expected = nlohmann::json::parse(full_stream);
  const nlohmann::json got = nlohmann::json::parse(fast_stream);
  EXPECT_EQ(got["accuracy"], expected["accuracy"]);
  std::size_t rejected = 0;
  for (std::size_t i = 0; i < objects_.size(); ++i) {
    EXPECT_EQ(got["objects"][i]["predictions"], expected["objects"][i]["predictions"]) << i;
    for (const auto& [model, pair] : got["objects"][i]["per_model"].items()) {
      const nlohmann::json& reference = expected["objects"][i]["per_model"][model];
      if (pair.value("rejected", false)) {
        ++rejected;
        EXPECT_TRUE(pair["fitness"].is_null());
        EXPECT_TRUE(reference["fitness"].is_number());
      } else {
        EXPECT_EQ(pair, reference) << i << " " << model;
      }
    }
  }
  EXPECT_GE(rejected, objects_.size());  // most objects have two models they cannot be
}

TEST_F(ClassifyFolderTest, AMissingModelIsAWarningAndItsObjectsCountAsWrong) {
  fs::remove(root_ / "models" / "Tall.pcd");
  const ClassificationRun run =
      classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kIcp, converging());
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings[0].find("Tall (6)"), std::string::npos) << run.warnings[0];
  EXPECT_EQ(run.summary(3).correct, objects_.size() / 2);
}

TEST_F(ClassifyFolderTest, BadFoldersAndFramesAreErrors) {
  EXPECT_THROW(classifyFolder(root_ / "none", root_ / "objects", RegistrationMethod::kIcp, {}),
               std::runtime_error);
  fs::create_directories(root_ / "empty");
  EXPECT_THROW(classifyFolder(root_ / "models", root_ / "empty", RegistrationMethod::kIcp, {}),
               std::runtime_error);
  // A model centred on its box (z = 0 at half height) is not in the objects' frame.
  writeModelPcd(root_ / "models" / "Long.pcd",
                shifted(models_[0].cloud, Eigen::Vector3f(0.0f, 0.0f, -0.7f)));
  try {
    classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kIcp, {});
    FAIL() << "a box-centred model was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("Long.pcd"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("box-centre frame"), std::string::npos);
  }
}

TEST_F(ClassifyFolderTest, AnUnreadableObjectIsAnErrorNamingTheFirstInTheFolder) {
  // Objects are read on several threads; the error names the first bad file in name order.
  for (const char* name : {"Tall-900-1.pcd", "Long-900-1.pcd"}) {
    std::ofstream(root_ / "objects" / name) << "not a PCD\n";
  }
  RegisterOptions threads;
  threads.threads = 4;
  ClassifyFolderOptions options;
  options.registration = threads;
  try {
    classifyFolder(root_ / "models", root_ / "objects", RegistrationMethod::kIcp, converging(),
                   options);
    FAIL() << "an unreadable object was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("Long-900-1.pcd"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace granular
