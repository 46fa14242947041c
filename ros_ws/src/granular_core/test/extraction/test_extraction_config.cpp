// ExtractionConfig validation.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/extraction/extraction_config.h"

namespace granular {
namespace {

TEST(ExtractionConfigTest, ValidateNamesTheBadField) {
  EXPECT_NO_THROW(validate(ExtractionConfig()));
  ExtractionConfig config;
  config.padding.y() = -0.1;
  EXPECT_THROW(validate(config), std::invalid_argument);
  config = ExtractionConfig();
  config.n_thresh = {};
  EXPECT_THROW(validate(config), std::invalid_argument);
  config.n_thresh = {10, 0};
  try {
    validate(config);
    FAIL() << "n_thresh with 0 accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("n_thresh"), std::string::npos);
  }
}

}  // namespace
}  // namespace granular
