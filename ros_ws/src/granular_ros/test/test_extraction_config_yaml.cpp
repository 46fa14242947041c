#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <granular_core/extraction/extraction_config.h>

#include "granular_ros/config_file.h"
#include "temporary_yaml.h"

namespace granular_ros {
namespace {

namespace fs = std::filesystem;

TEST(ExtractionConfigYamlTest, ShippedConfigLoadsAndValidates) {
  const fs::path file = fs::path(GRANULAR_CONFIG_DIR) / "extraction.yaml";
  granular::ExtractionConfig config;
  config.n_thresh = {999};
  config.labels = {"Leftover"};
  ASSERT_NO_THROW(loadConfigFile(file, config));
  EXPECT_NO_THROW(granular::validate(config));
  // The shipped file states the code's defaults.
  const granular::ExtractionConfig defaults;
  EXPECT_EQ(config.padding, defaults.padding);
  EXPECT_EQ(config.n_thresh, defaults.n_thresh);
  EXPECT_EQ(config.labels, defaults.labels);
}

class BadConfigTest : public TemporaryYamlTest {
 protected:
  std::string errorOf(const std::string& content) const {
    return TemporaryYamlTest::errorOf(content, [](const fs::path& file) {
      granular::ExtractionConfig config;
      loadConfigFile(file, config);
    });
  }
};

TEST_F(BadConfigTest, ErrorsNameTheFileAndTheKey) {
  EXPECT_NE(errorOf("padding: [0, 0, 0]\nn_tresh: [10]\n").find("n_tresh: unknown key"),
            std::string::npos);
  EXPECT_NE(errorOf("padding: [0, 0.1]\n").find("padding: expected three values"),
            std::string::npos);
  EXPECT_NE(errorOf("padding: [0, wide, 0]\n").find("padding[1]: expected a number"),
            std::string::npos);
  EXPECT_NE(errorOf("n_thresh: 10\n").find("n_thresh: expected a list"), std::string::npos);
  EXPECT_NE(errorOf("n_thresh: [10, 2.5]\n").find("n_thresh[1]: expected an integer"),
            std::string::npos);
  EXPECT_NE(errorOf("n_thresh: [-3]\n").find("n_thresh[0]: must be at least 1"),
            std::string::npos);
  EXPECT_NE(errorOf("labels: [Sedan, [SUV]]\n").find("labels[1]: expected a label"),
            std::string::npos);
  EXPECT_NE(errorOf("[1, 2]\n").find("expected a mapping"), std::string::npos);
  EXPECT_NE(errorOf("padding: [0, 0\n").find("not valid YAML"), std::string::npos);
}

TEST_F(BadConfigTest, KeysLeftOutKeepTheirValues) {
  write("labels: [Sedan, SUV]\n");
  granular::ExtractionConfig config;
  config.n_thresh = {10, 50};
  loadConfigFile(file_, config);
  EXPECT_EQ(config.labels, (std::vector<std::string>{"Sedan", "SUV"}));
  EXPECT_EQ(config.n_thresh, (std::vector<std::size_t>{10, 50}));
}

}  // namespace
}  // namespace granular_ros
