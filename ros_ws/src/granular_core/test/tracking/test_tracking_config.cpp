// TrackingConfig: the defaults are valid, and a value out of range names its field.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "granular_core/tracking/tracking_config.h"

namespace granular {
namespace {

std::string problem(const TrackingConfig& config) {
  try {
    validate(config);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(TrackingConfigTest, TheDefaultsAreValidAndBadValuesNameTheirField) {
  EXPECT_EQ(problem(TrackingConfig()), "");
  TrackingConfig config;
  config.gate.max_distance = 0.0;
  EXPECT_NE(problem(config).find("gate.max_distance"), std::string::npos);
  config = TrackingConfig();
  config.gate.max_sideways = 0.0;  // a track seen once could take no detection
  EXPECT_NE(problem(config).find("gate.max_sideways"), std::string::npos);
  config = TrackingConfig();
  config.filter.yaw_window = 0;  // the yaw would follow no detection
  EXPECT_NE(problem(config).find("filter.yaw_window"), std::string::npos);
  config = TrackingConfig();
  config.death_misses = 0;
  EXPECT_NE(problem(config).find("death_misses"), std::string::npos);
  config = TrackingConfig();
  config.abstain_label = "";
  EXPECT_NE(problem(config).find("abstain_label"), std::string::npos);
}

}  // namespace
}  // namespace granular
