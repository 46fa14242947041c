// A models folder as build_models writes it: every top-level <Class>.pcd, in label order, and
// the folders that are no models folder refused with the reason.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/dataset/models_folder.h"
#include "granular_core/dataset/pcd_io.h"
#include "support/temporary_folder.h"

namespace granular {
namespace {
using testing_support::TemporaryFolderTest;

namespace fs = std::filesystem;

using ModelsFolderTest = TemporaryFolderTest;

// `count` points in the object frame: a column from the road up, at x = `x`.
ModelCloud column(float x, int count, float bottom = 0.0f) {
  ModelCloud cloud;
  for (int i = 0; i < count; ++i) {
    cloud.push_back(pcl::PointXYZ(x, 0.0f, bottom + 0.1f * static_cast<float>(i)));
  }
  return cloud;
}

std::string errorReading(const fs::path& folder) {
  try {
    readClassModels(folder);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST_F(ModelsFolderTest, EveryTopLevelModelInLabelOrderAndNothingElse) {
  writeModelPcd(root_ / "Sedan.pcd", column(1.0f, 3));
  writeModelPcd(root_ / "BoxTruck.pcd", column(2.0f, 5));
  fs::create_directories(root_ / "raw");
  writeModelPcd(root_ / "raw" / "Jeep.pcd", column(3.0f, 4));  // build_models' raw/: no model
  writeModelPcd(root_ / ".Hidden.pcd", column(4.0f, 4));
  write("models.json", "{}");
  const std::vector<LabelledModel> models = readClassModels(root_);
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(models[0].label, "BoxTruck");
  EXPECT_EQ(models[0].cloud.size(), 5u);
  EXPECT_EQ(models[0].cloud.points[4].z, 0.4f);
  EXPECT_EQ(models[1].label, "Sedan");
  EXPECT_EQ(models[1].cloud.size(), 3u);
}

TEST_F(ModelsFolderTest, AModelInABoxCentredFrameIsRefused) {
  // Half its points below the road: a cloud centred on its box, not standing on the road.
  const ModelCloud centred = column(1.0f, 10, -0.55f);
  EXPECT_EQ(pointsBelow(centred, -0.1), 5u);  // -0.55 ... -0.15
  EXPECT_TRUE(looksBoxCentred(centred));
  EXPECT_FALSE(looksBoxCentred(column(1.0f, 10, -0.05f)));  // noise just below the road
  writeModelPcd(root_ / "Sedan.pcd", centred);
  const std::string error = errorReading(root_);
  EXPECT_EQ(error.rfind((root_ / "Sedan.pcd").string() + ": 50", 0), 0u) << error;
  EXPECT_NE(error.find("box-centre frame"), std::string::npos) << error;
}

TEST_F(ModelsFolderTest, AFolderWithoutModelsIsRefusedNamingIt) {
  write("notes.txt", "no models here");
  EXPECT_EQ(errorReading(root_),
            root_.string() + ": no class models (<Class>.pcd) in this folder");
  EXPECT_EQ(errorReading(root_ / "missing"), (root_ / "missing").string() +
                                                 ": no such models folder");
}

}  // namespace
}  // namespace granular
