#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <granular_core/models/model_config.h>

#include "granular_ros/config_file.h"
#include "temporary_yaml.h"

namespace granular_ros {
namespace {

namespace fs = std::filesystem;
using granular::FilterStage;

TEST(ModelConfigYamlTest, ShippedConfigStatesTheDefaults) {
  const fs::path file = fs::path(GRANULAR_CONFIG_DIR) / "models.yaml";
  granular::ModelBuildConfig config;
  // Values the file must set back.
  config.method = granular::ConcatenationMethod::kIcp;
  config.filters.voxel_grid.leaf_size = 0.5;
  config.filters.order = {FilterStage::kVoxelGrid};
  config.icp.max_fitness = 1.0;
  config.mesh.mu = 9.0;
  config.class_filters["SchoolBus"]["voxel_grid"]["leaf_size"] = 9.0;
  ASSERT_NO_THROW(loadConfigFile(file, config));
  EXPECT_NO_THROW(granular::validate(config));
  const granular::ModelBuildConfig defaults;
  EXPECT_TRUE(config == defaults);
  EXPECT_TRUE(config.filters == defaults.filters);
  EXPECT_TRUE(config.icp == defaults.icp);
  EXPECT_TRUE(config.class_filters == defaults.class_filters);
  EXPECT_TRUE(config.mesh == defaults.mesh);
}

class BadModelConfigTest : public TemporaryYamlTest {
 protected:
  std::string errorOf(const std::string& content) const {
    return TemporaryYamlTest::errorOf(content, [](const fs::path& file) {
      granular::ModelBuildConfig config;
      loadConfigFile(file, config);
    });
  }

  bool mentions(const std::string& content, const std::string& expected) const {
    const std::string message = errorOf(content);
    return message.find(expected) != std::string::npos;
  }
};

TEST_F(BadModelConfigTest, ErrorsNameTheFileAndTheKey) {
  EXPECT_TRUE(mentions("methd: icp\n", "methd: unknown key"));
  EXPECT_TRUE(mentions("method: nearest\n", "method: expected plain or icp"));
  EXPECT_TRUE(mentions("filters:\n  voxel_grid: {leaf: 0.1}\n",
                       "filters.voxel_grid.leaf: unknown key (known: leaf_size)"));
  EXPECT_TRUE(mentions("filters:\n  voxel_grid: {leaf_size: fine}\n",
                       "filters.voxel_grid.leaf_size: expected a number, got 'fine'"));
  EXPECT_TRUE(mentions("filters:\n  statistical_outlier: {mean_k: 5.5}\n",
                       "filters.statistical_outlier.mean_k: expected an integer"));
  EXPECT_TRUE(mentions("filters:\n  order: voxel_grid\n", "filters.order: expected a list"));
  EXPECT_TRUE(mentions("filters:\n  order: [pass_through, ground]\n",
                       "filters.order[1]: unknown stage 'ground'"));
  EXPECT_TRUE(mentions("filters:\n  pass_through: [0.2, 2.0]\n",
                       "filters.pass_through: expected a mapping"));
  EXPECT_TRUE(mentions("class_filters:\n  SchoolBus: {pass_through: {maxz: 3.4}}\n",
                       "class_filters.SchoolBus.pass_through.maxz: unknown key"));
  EXPECT_TRUE(mentions("icp: {max_iterations: many}\n", "icp.max_iterations: expected an integer"));
  EXPECT_TRUE(mentions("seed: {objects_per_side: -1}\n",
                       "seed.objects_per_side: must not be negative"));
  EXPECT_TRUE(mentions("mesh: {mu: [1]}\n", "mesh.mu: expected a number"));
  EXPECT_TRUE(mentions("[1, 2]\n", "expected a mapping"));
  EXPECT_TRUE(mentions("filters: {order: [voxel_grid\n", "not valid YAML"));
}

TEST_F(BadModelConfigTest, KeysLeftOutKeepTheirValuesAndOverridesMerge) {
  write("method: icp\n"
        "filters:\n  voxel_grid: {leaf_size: 0.12}\n"
        "class_filters:\n"
        "  SchoolBus: {voxel_grid: {leaf_size: 0.2}}\n"
        "  Pedestrian: {order: [pass_through, voxel_grid]}\n");
  granular::ModelBuildConfig config;
  config.icp.max_fitness = 0.02;
  loadConfigFile(file_, config);
  EXPECT_EQ(config.method, granular::ConcatenationMethod::kIcp);
  EXPECT_EQ(config.icp.max_fitness, 0.02);
  EXPECT_EQ(config.filtersFor("Van").voxel_grid.leaf_size, 0.12);
  EXPECT_EQ(config.filtersFor("Pedestrian").voxel_grid.leaf_size, 0.12);
  const granular::FilterChainConfig bus = config.filtersFor("SchoolBus");
  EXPECT_EQ(bus.voxel_grid.leaf_size, 0.2);
  EXPECT_EQ(bus.pass_through.max_z, granular::ModelBuildConfig().filtersFor("SchoolBus")
                                        .pass_through.max_z);  // the default override stays
  EXPECT_EQ(config.filtersFor("Pedestrian").order,
            (std::vector<FilterStage>{FilterStage::kPassThrough, FilterStage::kVoxelGrid}));
}

}  // namespace
}  // namespace granular_ros
