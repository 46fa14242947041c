// Registration states: what counts as convergence.

#include <gtest/gtest.h>

#include "granular_core/registration/registration.h"

namespace granular {
namespace {

TEST(ConvergenceTest, ReachingTheIterationLimitIsNotConvergence) {
  for (const char* name : {"transform", "abs_mse", "rel_mse"}) {
    EXPECT_TRUE(isConverged(*registrationStateFromName(name))) << name;
  }
  for (const char* name : {"iterations", "no_correspondences", "failed", "too_few_points"}) {
    EXPECT_FALSE(isConverged(*registrationStateFromName(name))) << name;
  }
}

}  // namespace
}  // namespace granular
