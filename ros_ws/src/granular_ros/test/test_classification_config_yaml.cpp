#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <granular_core/registration/registration_config.h>

#include "granular_ros/config_file.h"
#include "temporary_yaml.h"

namespace granular_ros {
namespace {

namespace fs = std::filesystem;
using Presets = std::map<std::string, granular::RegistrationClassifierConfig>;

// The presets of `file` laid over `presets`.
void loadRegistrationPresets(const fs::path& file, Presets& presets) {
  granular::RegistrationPresets loaded;
  loaded.presets = presets;
  loadConfigFile(file, loaded);
  presets = loaded.presets;
}

TEST(ClassificationConfigYamlTest, ShippedConfigStatesTheBuiltInPresets) {
  Presets presets;
  // Values the file must set back.
  presets["report"].icp.max_iterations = 99;
  presets["tuned"].ndt.resolution = 9.0;
  presets["tuned"].source_min_z.reset();
  presets["report"].source_max_points = 7;
  ASSERT_NO_THROW(loadRegistrationPresets(fs::path(GRANULAR_CONFIG_DIR) / "classification.yaml",
                                          presets));
  const Presets built_in = granular::registrationPresets();
  ASSERT_EQ(presets.size(), built_in.size());
  for (const auto& [name, config] : built_in) {
    EXPECT_NO_THROW(granular::validate(presets.at(name))) << name;
    EXPECT_TRUE(presets.at(name) == config) << name;
  }
  // The report preset is the report's values (sections 8.1.1 and 8.3).
  const granular::RegistrationClassifierConfig& report = presets.at("report");
  EXPECT_EQ(report.icp.max_iterations, 1);
  EXPECT_EQ(report.icp.max_correspondence_distance, 0.01);
  EXPECT_EQ(report.icp.transformation_epsilon, 1e-9);
  EXPECT_EQ(report.icp.euclidean_fitness_epsilon, 0.001);
  EXPECT_EQ(report.icp.coarse_iterations, 0);  // one stage
  EXPECT_EQ(report.icp_nl.coarse_iterations, 0);
  EXPECT_EQ(report.ndt.transformation_epsilon, 0.01);
  EXPECT_EQ(report.ndt.step_size, 0.1);
  EXPECT_EQ(report.ndt.max_iterations, 35);
  EXPECT_EQ(report.ndt.resolution, 0.1);
  EXPECT_FALSE(report.source_min_z);
  EXPECT_EQ(report.source_max_points, 0u);  // every point
  // fast is tuned on at most 50 points an object.
  granular::RegistrationClassifierConfig fast = presets.at("tuned");
  fast.source_max_points = 50;
  EXPECT_TRUE(presets.at("fast") == fast);
}

class BadClassificationConfigTest : public TemporaryYamlTest {
 protected:
  std::string errorOf(const std::string& content) const {
    return TemporaryYamlTest::errorOf(content, [](const fs::path& file) {
      Presets presets = granular::registrationPresets();
      loadRegistrationPresets(file, presets);
    });
  }
};

TEST_F(BadClassificationConfigTest, ErrorsNameTheFileAndTheKey) {
  EXPECT_NE(errorOf("presets:\n  tuned:\n    ndt: {resolutin: 0.3}\n")
                .find("presets.tuned.ndt.resolutin: unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf("presets:\n  tuned:\n    icp: {max_iterations: many}\n")
                .find("presets.tuned.icp.max_iterations: expected an integer, got 'many'"),
            std::string::npos);
  EXPECT_NE(errorOf("presets:\n  tuned:\n    source_max_points: -100\n")
                .find("presets.tuned.source_max_points"),
            std::string::npos);
  EXPECT_NE(errorOf("preset: {}\n").find("preset: unknown key (known: presets)"),
            std::string::npos);
  EXPECT_NE(errorOf("presets: [report]\n").find("presets: expected a mapping"),
            std::string::npos);
}

TEST_F(BadClassificationConfigTest, ANewPresetStartsFromTheReportsValues) {
  write("presets:\n  mine:\n    icp: {max_iterations: 7}\n"
        "    source_min_z: 0.25\n  tuned:\n    source_min_z: null\n");
  Presets presets = granular::registrationPresets();
  loadRegistrationPresets(file_, presets);
  granular::RegistrationClassifierConfig expected;
  expected.icp.max_iterations = 7;
  expected.source_min_z = 0.25;
  EXPECT_TRUE(presets.at("mine") == expected);
  EXPECT_FALSE(presets.at("tuned").source_min_z);
  EXPECT_EQ(presets.at("tuned").ndt.resolution,
            granular::registrationPresets().at("tuned").ndt.resolution);
}

}  // namespace
}  // namespace granular_ros
