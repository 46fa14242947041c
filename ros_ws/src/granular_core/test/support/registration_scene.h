// Two clearly different class models and views of them, in memory (RegistrationTest) and on
// disk (ClassifyFolderTest): shared by the registration, online and run tests.
#pragma once

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/dataset/pcd_io.h"
#include "granular_core/registration/registration_config.h"
#include "granular_core/dataset/models_folder.h"
#include "support/model_clouds.h"

namespace granular {
namespace testing_support {

namespace fs = std::filesystem;
using testing_clouds::boxSurface;
using testing_clouds::shifted;

// Two clearly different class models in the object frame, and partial views of each.
class RegistrationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 random(5);
    models_.push_back({"Long", boxSurface({4.6, 1.8, 1.4}, 4000, random)});
    models_.push_back({"Tall", boxSurface({2.0, 1.6, 2.6}, 4000, random)});
    for (int i = 0; i < 6; ++i) {
      // A view of the left side and the front, a few centimetres off, as extraction gives.
      const Eigen::Vector3f offset(0.02f * (i % 3), -0.015f * (i % 2), 0.0f);
      for (std::size_t m = 0; m < models_.size(); ++m) {
        ModelCloud view;
        for (const pcl::PointXYZ& p : models_[m].cloud.points) {
          if ((p.y > 0.5f || p.x > 0.8f) && view.size() < 300) {
            view.push_back(p);
          }
        }
        objects_.push_back(shifted(view, offset));
        truth_.push_back(m);
      }
    }
  }

  static RegistrationClassifierConfig converging() {
    RegistrationClassifierConfig config;
    config.icp.max_iterations = 30;
    config.icp.max_correspondence_distance = 0.1;
    config.icp_nl = config.icp;
    config.ndt.resolution = 0.5;
    return config;
  }

  // converging() with pairs up to 5 cm after a coarse stage of 3 iterations up to 10 cm.
  static RegistrationClassifierConfig withCoarseStage() {
    RegistrationClassifierConfig config = converging();
    config.icp.max_correspondence_distance = 0.05;
    config.icp.coarse_iterations = 3;
    config.icp.coarse_correspondence_distance = 0.1;
    config.icp_nl = config.icp;
    return config;
  }

  std::vector<LabelledModel> models_;
  std::vector<ModelCloud> objects_;
  std::vector<std::size_t> truth_;
};

// A models folder and an objects folder of the shapes of RegistrationTest, on disk.
class ClassifyFolderTest : public RegistrationTest {
 protected:
  void SetUp() override {
    RegistrationTest::SetUp();
    std::random_device entropy;
    root_ = fs::temp_directory_path() /
            ("granular_classify_test_" + std::to_string(entropy()) + std::to_string(entropy()));
    fs::create_directories(root_ / "models");
    fs::create_directories(root_ / "objects");
    for (const LabelledModel& model : models_) {
      writeModelPcd(root_ / "models" / (model.label + ".pcd"), model.cloud);
    }
    for (std::size_t i = 0; i < objects_.size(); ++i) {
      writeModelPcd(root_ / "objects" /
                        (models_[truth_[i]].label + "-" + std::to_string(100 + i) + "-1.pcd"),
                    objects_[i]);
    }
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_;
};

}  // namespace testing_support
}  // namespace granular
