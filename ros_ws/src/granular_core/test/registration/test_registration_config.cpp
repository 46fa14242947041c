// RegistrationClassifierConfig and the classifier's refusals.
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "granular_core/registration/registration_classifier.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::boxSurface;

TEST(ClassifierConfigTest, RefusesBadInput) {
  RegistrationClassifierConfig config;
  config.ndt.resolution = 0.0;
  EXPECT_THROW(validate(config), std::invalid_argument);
  config = RegistrationClassifierConfig();
  config.icp_nl.coarse_iterations = -1;
  EXPECT_THROW(validate(config), std::invalid_argument);
  config = RegistrationClassifierConfig();
  config.icp.coarse_correspondence_distance = 0.0;
  EXPECT_THROW(validate(config), std::invalid_argument);
  std::mt19937 random(1);
  const LabelledModel model{"A", boxSurface({1, 1, 1}, 100, random)};
  EXPECT_THROW(RegistrationClassifier(RegistrationMethod::kIcp, {}, {}), std::invalid_argument);
  EXPECT_THROW(RegistrationClassifier(RegistrationMethod::kIcp, {}, {model, model}),
               std::invalid_argument);
  EXPECT_THROW(RegistrationClassifier(RegistrationMethod::kIcp, {}, {{"B", ModelCloud()}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace granular
