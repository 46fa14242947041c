// The shipped config/supervised.yaml, segmentation.yaml, ground.yaml, cuboids.yaml and tracking.yaml load, validate, and
// state the defaults (where they differ on purpose, the test says which value and why).
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <granular_core/cuboids/cuboid_config.h>
#include <granular_core/segmentation/object_segmentation.h>
#include <granular_core/supervised/supervised_classifier.h>
#include <granular_core/tracking/tracking_config.h>

#include "granular_ros/box_free_options.h"
#include "granular_ros/config_file.h"
#include "temporary_yaml.h"

namespace granular_ros {
namespace {

namespace fs = std::filesystem;

TEST(ShippedConfigTest, SupervisedYamlStatesTheDefaults) {
  granular::SupervisedConfig config;
  config.knn.k = 9;  // values the file must set back
  config.svm.nu = {0.9};
  config.histograms.bins = 3;
  config.histograms.scatter = granular::ScatterDefinition::kLargest;
  ASSERT_NO_THROW(loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "supervised.yaml", config));
  EXPECT_NO_THROW(granular::validate(config));
  const granular::SupervisedConfig defaults;
  EXPECT_EQ(config.knn.k, defaults.knn.k);
  EXPECT_EQ(config.knn.standardize, defaults.knn.standardize);
  EXPECT_EQ(config.svm.nu, defaults.svm.nu);
  EXPECT_EQ(config.svm.log2_gamma_min, defaults.svm.log2_gamma_min);
  EXPECT_EQ(config.svm.folds, defaults.svm.folds);
  EXPECT_EQ(granular::featureConfigDifference(granular::SupervisedMethod::kSvm,
                                              config.histograms, defaults.histograms),
            "");
}

TEST(ShippedConfigTest, SegmentationYamlStatesThePapersValuesButTheLink) {
  granular::SegmentationStageConfig stage;
  stage.occupancy.cell_size = 1.0;
  stage.occupancy.height_threshold = 1.0;
  ASSERT_NO_THROW(loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "segmentation.yaml", stage));
  EXPECT_NO_THROW(granular::validate(stage));
  const granular::SegmentationConfig& config = stage.occupancy;
  const granular::SegmentationConfig defaults;
  EXPECT_EQ(config.cell_size, defaults.cell_size);
  EXPECT_EQ(config.extent, defaults.extent);
  EXPECT_EQ(config.height_threshold, defaults.height_threshold);
  EXPECT_EQ(config.min_cells, defaults.min_cells);
  EXPECT_EQ(config.min_points, defaults.min_points);
  EXPECT_EQ(config.max_length, defaults.max_length);
  // The simulated LiDAR's 1 deg azimuth step needs gaps bridged (docs/online.md).
  EXPECT_EQ(config.link_cells, 3);
}

TEST(ShippedConfigTest, SegmentationYamlStatesTheObjectSegmentationDefaults) {
  granular::SegmentationStageConfig stage;
  stage.objects.gates.min_top = 9.0;
  ASSERT_NO_THROW(loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "segmentation.yaml", stage));
  EXPECT_TRUE(stage.objects == granular::ObjectSegmentationConfig());
  EXPECT_EQ(stage.method, granular::SegmentationMethod::kObjects);
}

TEST(ShippedConfigTest, GroundYamlStatesTheGroundDefaults) {
  granular::GroundConfig ground;
  ground.plane.eps_angle_deg = 45.0;
  ground.lines.sectors = 7;
  ASSERT_NO_THROW(loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "ground.yaml", ground));
  EXPECT_TRUE(ground == granular::GroundConfig());
}

TEST(ShippedConfigTest, EverySensorFileLoadsAndValidates) {
  // config/sensors/*.yaml, by name as --sensor NAME reads them; the simulator's states the
  // SensorConfig defaults (the simulated LiDAR), KITTI's the HDL-64E as mounted there.
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(GRANULAR_CONFIG_DIR) / "sensors")) {
    SCOPED_TRACE(entry.path().string());
    ASSERT_NO_THROW(loadSensorFile(entry.path().stem().string()));
    ++files;
  }
  EXPECT_EQ(files, 5u);
  const granular::SensorConfig simulator = loadSensorFile("simulator");
  const granular::SensorConfig defaults;
  EXPECT_EQ(simulator.mount_height, defaults.mount_height);
  EXPECT_EQ(simulator.azimuth_step_deg, defaults.azimuth_step_deg);
  EXPECT_EQ(simulator.rings, defaults.rings);
  EXPECT_EQ(loadSensorFile("hdl64e").mount_height, 1.73);
  EXPECT_EQ(loadSensorFile("hdl64e").azimuth_step_deg, 0.176);
}

class SensorFileTest : public TemporaryYamlTest {
 protected:
  std::string fileName() const { return file_.string(); }
};

TEST_F(SensorFileTest, ABadSensorIsRefusedNamingIt) {
  try {
    loadSensorFile("hdl46e");
    FAIL() << "an unknown sensor name was taken";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("hdl64e"), std::string::npos) << error.what();
  }
  write("description: x\nmount_height: -1.0\nazimuth_step_deg: 0.2\nrings: 16\n"
        "min_elevation_deg: -15\nmax_elevation_deg: 15\nmin_range: 0.5\nmax_range: 100\n"
        "rate_hz: 10\n");
  EXPECT_THROW(loadSensorFile(fileName()), std::invalid_argument);
  write("description: x\nmount_height: 1.9\nazimuth_step_deg: 0.0\nrings: 16\n"
        "min_elevation_deg: -15\nmax_elevation_deg: 15\nmin_range: 0.5\nmax_range: 100\n"
        "rate_hz: 10\n");
  EXPECT_THROW(loadSensorFile(fileName()), std::invalid_argument);
}

TEST(ShippedConfigTest, CuboidsYamlStatesTheCuboidDefaults) {
  granular::CuboidConfig cuboids;
  cuboids.lshape.closeness_d0 = 0.01;
  cuboids.priors.at("Car").length = 5.0;
  cuboids.model.registration.icp.max_iterations = 3;
  ASSERT_NO_THROW(loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "cuboids.yaml", cuboids));
  // The file leaves the registration out; the rest it states.
  cuboids.model.registration = granular::CuboidConfig().model.registration;
  EXPECT_TRUE(cuboids == granular::CuboidConfig());
}

TEST(ShippedConfigTest, TrackingYamlStatesTheTrackingDefaults) {
  granular::TrackingConfig tracking;
  tracking.gate.min_overlap = 0.0;  // values the file must set back
  tracking.gate.max_sideways = 5.0;
  tracking.filter.yaw_window = 1;
  tracking.birth_misses = 0;
  tracking.vote = granular::ClassVote::kVotes;
  tracking.bridge_frames = 0;
  tracking.backfill_gap = 0;
  tracking.final_class = false;
  ASSERT_NO_THROW(loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "tracking.yaml", tracking));
  EXPECT_NO_THROW(granular::validate(tracking));
  EXPECT_TRUE(tracking == granular::TrackingConfig());
}

TEST(ShippedConfigTest, TrackingOnlineYamlBearsTracksAfterThreeCloudsAndEndsThemAfterTwelve) {
  // online.launch loads it over tracking.yaml: the births and deaths differ, and no ended
  // tentative track is kept (nothing can be written back online).
  granular::TrackingConfig tracking;
  ASSERT_NO_THROW(loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "tracking.yaml", tracking));
  ASSERT_NO_THROW(
      loadConfigFile(fs::path(GRANULAR_CONFIG_DIR) / "tracking_online.yaml", tracking));
  EXPECT_NO_THROW(granular::validate(tracking));
  EXPECT_EQ(tracking.birth_hits, 3u);
  EXPECT_EQ(tracking.death_misses, 12u);
  EXPECT_EQ(tracking.backfill_gap, 0u);
  tracking.birth_hits = granular::TrackingConfig().birth_hits;
  tracking.death_misses = granular::TrackingConfig().death_misses;
  tracking.backfill_gap = granular::TrackingConfig().backfill_gap;
  EXPECT_TRUE(tracking == granular::TrackingConfig());
}

using ShippedConfigKeysTest = TemporaryYamlTest;

TEST_F(ShippedConfigKeysTest, BadValuesNameTheFileAndTheKey) {
  const auto supervised = [](const fs::path& file) {
    granular::SupervisedConfig config;
    loadConfigFile(file, config);
  };
  const auto segmentation = [](const fs::path& file) {
    granular::SegmentationConfig config;
    loadConfigFile(file, config);
  };
  EXPECT_NE(errorOf("histograms: {scatter: middle}\n", supervised)
                .find("histograms.scatter: expected smallest or largest, got 'middle'"),
            std::string::npos);
  EXPECT_NE(errorOf("knn: {standardize: maybe}\n", supervised)
                .find("knn.standardize: expected true or false"),
            std::string::npos);
  EXPECT_NE(errorOf("cell: 0.2\n", segmentation).find(file_.string() + ": cell: unknown key"),
            std::string::npos);
}

}  // namespace
}  // namespace granular_ros
