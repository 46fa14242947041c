#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "granular_core/dataset/pcd_io.h"
#include "granular_core/dataset/object_names.h"
#include "granular_core/runs/build_models_run.h"
#include "support/model_clouds.h"

namespace granular {
namespace {

namespace fs = std::filesystem;

Cloud toCloud(const ModelCloud& model) {
  Cloud cloud;
  for (const pcl::PointXYZ& p : model.points) {
    cloud.push_back(PointXYZIT(p.x, p.y, p.z, 10, 1.5));
  }
  return cloud;
}

// An objects folder with two Sedans (3000 and 2000 points) and one SUV (1500), under a fresh
// temporary folder removed with the fixture.
class ModelsFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device entropy;
    root_ = fs::temp_directory_path() /
            ("granular_models_test_" + std::to_string(entropy()) + std::to_string(entropy()));
    objects_ = root_ / "objects";
    out_ = root_ / "models";
    fs::create_directories(objects_);
    std::mt19937 random(13);
    const Eigen::Vector3d car(4.4, 1.8, 1.5);
    writePcdBinary(objects_ / "Sedan-100-1.pcd",
                   toCloud(testing_clouds::boxSurface(car, 3000, random)));
    writePcdBinary(objects_ / "Sedan-200-1.pcd",
                   toCloud(testing_clouds::boxSurface(car, 2000, random)));
    writePcdBinary(objects_ / "SUV-100-2.pcd",
                   toCloud(testing_clouds::boxSurface({4.8, 1.9, 1.8}, 1500, random)));
    std::ofstream(objects_ / "index.csv") << "file,label\n";
  }
  void TearDown() override { fs::remove_all(root_); }

  nlohmann::json modelsJson() const {
    std::ifstream stream(out_ / "models.json");
    return nlohmann::json::parse(stream);
  }

  // Only the objects folder (and no staging folder) is left under the root.
  void expectNoOutput() const {
    for (const fs::directory_entry& entry : fs::directory_iterator(root_)) {
      EXPECT_EQ(entry.path(), objects_) << "left behind: " << entry.path();
    }
  }

  fs::path root_, objects_, out_;
};

TEST_F(ModelsFolderTest, ListsObjectsByTheirNamePrefix) {
  std::ofstream(objects_ / "stray.pcd") << "x";
  std::vector<std::string> unnamed;
  const auto files = listObjectFiles(objects_, &unnamed);
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files.at("Sedan"),
            (std::vector<fs::path>{objects_ / "Sedan-100-1.pcd", objects_ / "Sedan-200-1.pcd"}));
  EXPECT_EQ(files.at("SUV"), std::vector<fs::path>{objects_ / "SUV-100-2.pcd"});
  EXPECT_EQ(unnamed, std::vector<std::string>{"stray.pcd"});
  EXPECT_EQ(objectClass("BoxTruck-1586102754700816458-1.pcd"), "BoxTruck");
}

TEST_F(ModelsFolderTest, WritesModelsRawCloudsAndTheirReport) {
  ModelBuildConfig config;
  std::vector<std::string> done;
  BuildModelsOptions options;
  options.mesh = true;
  options.class_done = [&](const ClassModelSummary& summary) { done.push_back(summary.label); };
  const BuildModelsSummary summary = buildModels(objects_, out_, config, options);
  EXPECT_EQ(done, (std::vector<std::string>{"SUV", "Sedan"}));
  ASSERT_EQ(summary.classes.size(), 2u);

  const ClassModelSummary& sedan = summary.classes[1];
  EXPECT_EQ(sedan.objects, 2u);
  EXPECT_EQ(sedan.kept, 2u);
  EXPECT_EQ(sedan.raw_points, 5000u);
  EXPECT_EQ(readModelPcd(out_ / "raw" / "Sedan.pcd").size(), 5000u);
  EXPECT_EQ(readModelPcd(out_ / "Sedan.pcd").size(), sedan.points);
  EXPECT_EQ(readModelPcd(out_ / "raw" / "SUV.pcd").size(), 1500u);
  EXPECT_TRUE(fs::is_regular_file(out_ / "mesh" / "Sedan.ply"));

  const nlohmann::json report = modelsJson();
  EXPECT_EQ(report["method"], "plain");
  const nlohmann::json& entry = report["classes"]["Sedan"];
  EXPECT_EQ(entry["objects"], 2);
  EXPECT_EQ(entry["kept"], 2);
  EXPECT_EQ(entry["raw_points"], 5000);
  ASSERT_EQ(entry["stages"].size(), 4u);
  EXPECT_EQ(entry["stages"][0]["stage"], "pass_through");
  EXPECT_EQ(entry["stages"][3]["points"], sedan.points);
  EXPECT_EQ(entry["points"], sedan.points);
  EXPECT_EQ(entry["filters"]["statistical_outlier"]["mean_k"], 5);
  EXPECT_EQ(entry["filters"]["voxel_grid"]["leaf_size"],
            config.filtersFor("Sedan").voxel_grid.leaf_size);
  EXPECT_EQ(entry["files"]["raw"], "raw/Sedan.pcd");
}

TEST_F(ModelsFolderTest, IcpReportsKeptObjectsAndWarnsForASingleObject) {
  ModelBuildConfig config;
  config.method = ConcatenationMethod::kIcp;
  const BuildModelsSummary summary = buildModels(objects_, out_, config);
  const nlohmann::json report = modelsJson();
  EXPECT_EQ(report["method"], "icp");
  EXPECT_EQ(report["icp"]["max_fitness"], config.icp.max_fitness);
  EXPECT_EQ(report["classes"]["SUV"]["kept"], 1);
  EXPECT_NE(report["classes"]["SUV"]["warnings"][0].get<std::string>().find("single object"),
            std::string::npos);
  EXPECT_EQ(report["classes"]["Sedan"]["icp"]["seed"]["source"], "auto");
  EXPECT_EQ(summary.classes[1].kept, 2u);
}

TEST_F(ModelsFolderTest, AClassWithoutObjectsIsReportedNotBuilt) {
  BuildModelsOptions options;
  options.classes = {"Sedan", "Truck"};
  const BuildModelsSummary summary = buildModels(objects_, out_, ModelBuildConfig(), options);
  ASSERT_EQ(summary.classes.size(), 2u);
  EXPECT_EQ(summary.classes[1].label, "Truck");
  EXPECT_EQ(summary.classes[1].objects, 0u);
  EXPECT_FALSE(fs::exists(out_ / "Truck.pcd"));
  EXPECT_FALSE(fs::exists(out_ / "SUV.pcd"));
  EXPECT_TRUE(fs::exists(out_ / "Sedan.pcd"));
  EXPECT_EQ(modelsJson()["classes"]["Truck"]["objects"], 0);

  options.classes = {"Truck"};
  EXPECT_THROW(buildModels(objects_, root_ / "other", ModelBuildConfig(), options),
               std::runtime_error);
}

// A real dataset's rare classes (one tram, pylons the filters empty) are left out and named;
// the classes with data get their models.
TEST_F(ModelsFolderTest, ClassesWithTooLittleDataAreLeftOutAndNamed) {
  ModelBuildConfig config;
  config.min_objects = 2;  // the SUV has one object
  // A band above the Sedans' roofs (1.5 m) empties their model.
  config.class_filters["Sedan"]["pass_through"] = {{"min_z", 5.0}, {"max_z", 6.0}};
  std::mt19937 random(3);
  for (const char* name : {"Bus-100-3.pcd", "Bus-200-3.pcd"}) {
    writePcdBinary(objects_ / name, toCloud(testing_clouds::boxSurface({11, 2.5, 3}, 2000,
                                                                       random)));
  }
  const BuildModelsSummary summary = buildModels(objects_, out_, config);

  ASSERT_EQ(summary.left_out.size(), 2u);
  EXPECT_NE(summary.left_out.at("SUV").find("1 object(s), fewer than min_objects 2"),
            std::string::npos);
  EXPECT_NE(summary.left_out.at("Sedan").find("pass_through"), std::string::npos);
  EXPECT_TRUE(fs::exists(out_ / "Bus.pcd"));
  EXPECT_FALSE(fs::exists(out_ / "SUV.pcd"));
  EXPECT_FALSE(fs::exists(out_ / "Sedan.pcd"));
  EXPECT_FALSE(fs::exists(out_ / "raw" / "Sedan.pcd"));
  const nlohmann::json report = modelsJson();
  EXPECT_EQ(report["left_out"].size(), 2u);
  EXPECT_EQ(report["classes"]["SUV"]["left_out"], summary.left_out.at("SUV"));
  EXPECT_FALSE(report["classes"]["Sedan"].contains("files"));
  EXPECT_EQ(report["min_objects"], 2);
  const std::string warnings = report["warnings"].dump();
  EXPECT_NE(warnings.find("class 'SUV' left out"), std::string::npos) << warnings;
  std::ostringstream table, log;
  summary.report(table, log);
  EXPECT_NE(table.str().find("2 classes left out (SUV, Sedan"), std::string::npos)
      << table.str();
  EXPECT_NE(log.str().find("class 'Sedan' left out"), std::string::npos) << log.str();
}

TEST_F(ModelsFolderTest, NoClassLeftIsAnErrorNamingEachClassAndWhy) {
  ModelBuildConfig config;
  config.min_points = 1000000;
  try {
    buildModels(objects_, out_, config);
    FAIL() << "built models with no class left";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("no class has enough data"), std::string::npos) << message;
    EXPECT_NE(message.find("class 'SUV': a model of "), std::string::npos) << message;
    EXPECT_NE(message.find("fewer than min_points 1000000"), std::string::npos) << message;
    EXPECT_NE(message.find("class 'Sedan'"), std::string::npos) << message;
  }
  expectNoOutput();
}

TEST_F(ModelsFolderTest, ReplacesOnlyItsOwnResultsAndOnlyWithOverwrite) {
  fs::create_directories(out_);
  std::ofstream(out_ / "keep.txt") << "mine";
  BuildModelsOptions options;
  options.output.overwrite = true;
  EXPECT_THROW(buildModels(objects_, out_, ModelBuildConfig(), options), std::runtime_error);
  EXPECT_TRUE(fs::exists(out_ / "keep.txt"));
  fs::remove(out_ / "keep.txt");

  buildModels(objects_, out_, ModelBuildConfig());
  EXPECT_THROW(buildModels(objects_, out_, ModelBuildConfig()), std::runtime_error);
  std::ofstream(out_ / "stale.pcd") << "from the first run";
  buildModels(objects_, out_, ModelBuildConfig(), options);
  EXPECT_FALSE(fs::exists(out_ / "stale.pcd"));
  EXPECT_TRUE(fs::exists(out_ / "Sedan.pcd"));
  // Never over its own input.
  EXPECT_THROW(buildModels(objects_, root_, ModelBuildConfig(), options), std::runtime_error);
  EXPECT_TRUE(fs::exists(objects_ / "Sedan-100-1.pcd"));
}

TEST_F(ModelsFolderTest, BadInputFailsWithoutPartialModels) {
  const auto message = [&](const fs::path& objects, const BuildModelsOptions& options) {
    try {
      buildModels(objects, out_, ModelBuildConfig(), options);
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  fs::create_directories(root_ / "empty");
  std::ofstream(root_ / "empty" / "index.csv") << "file\n";
  EXPECT_NE(message(root_ / "empty", {}).find("no object PCDs"), std::string::npos);
  EXPECT_NE(message(root_ / "missing", {}).find("no such objects folder"), std::string::npos);
  fs::remove_all(root_ / "empty");

  BuildModelsOptions seeded;
  seeded.seeds["Jeep"] = root_ / "jeep.pcd";
  EXPECT_NE(message(objects_, seeded).find("seed for class 'Jeep'"), std::string::npos);

  std::ofstream(objects_ / "Sedan-300-1.pcd") << "not a point cloud\n";
  EXPECT_NE(message(objects_, {}).find("Sedan-300-1.pcd"), std::string::npos);
  expectNoOutput();
}

}  // namespace
}  // namespace granular
