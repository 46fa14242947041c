// ModelBuildConfig: class overrides and validation.
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/models/model_config.h"

namespace granular {
namespace {

// ---- config --------------------------------------------------------------------------------

TEST(ModelConfigTest, ClassOverridesReplaceOnlyTheirValues) {
  ModelBuildConfig config;
  EXPECT_NO_THROW(validate(config));
  EXPECT_EQ(config.filtersFor("Pedestrian"), config.filters);
  EXPECT_EQ(config.filtersFor("Van"), config.filters);
  const FilterChainConfig bus = config.filtersFor("SchoolBus");
  EXPECT_EQ(bus.pass_through.min_z, 0.2);
  EXPECT_FALSE(bus.pass_through.max_z) << "the band's top follows the class's boxes";
  EXPECT_LT(bus.voxel_grid.leaf_size, 0.1);
  EXPECT_EQ(bus.statistical_outlier, config.filters.statistical_outlier);
  EXPECT_EQ(config.filtersFor("Sedan").pass_through, config.filters.pass_through);

  config.filters.statistical_outlier.mean_k = 8;
  config.class_filters["Pedestrian"]["order"] = {"pass_through", "voxel_grid"};
  EXPECT_EQ(config.filtersFor("SchoolBus").statistical_outlier.mean_k, 8);
  EXPECT_EQ(config.filtersFor("Pedestrian").order.size(), 2u);
}

TEST(ModelConfigTest, ValidateNamesTheField) {
  const auto message = [](const ModelBuildConfig& config) {
    try {
      validate(config);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  ModelBuildConfig config;
  config.filters.order.push_back(FilterStage::kVoxelGrid);
  EXPECT_NE(message(config).find("filters.order: stage voxel_grid is listed twice"),
            std::string::npos);
  config = ModelBuildConfig();
  config.class_filters["SUV"]["pass_through"] = {{"min_z", 2.5}, {"max_z", 2.0}};
  EXPECT_NE(message(config).find("class_filters.SUV: pass_through"), std::string::npos);
  config = ModelBuildConfig();
  config.filters.voxel_grid.leaf_size = 0.0;
  EXPECT_NE(message(config).find("voxel_grid.leaf_size"), std::string::npos);
  config = ModelBuildConfig();
  config.icp.max_fitness = -1.0;
  EXPECT_NE(message(config).find("icp.max_fitness"), std::string::npos);
}

}  // namespace
}  // namespace granular
