// The report's three criteria (section 8.1) on per-model results.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/registration/criteria.h"

namespace granular {
namespace {

PairResult pair(RegistrationState state, double fitness) {
  PairResult result;
  result.state = state;
  result.fitness = fitness;
  return result;
}

TEST(CriteriaTest, FollowTheReportsThreeRules) {
  const auto converged = RegistrationState::kTransform;
  const auto iterations = RegistrationState::kIterations;
  // Converged to exactly one model (index 1): all three criteria may differ.
  Predictions one = predict({pair(iterations, 0.01), pair(converged, 0.05), pair(iterations, 0.2)});
  EXPECT_EQ(one.criterion1, 1u);
  EXPECT_EQ(one.criterion2, 1u);
  EXPECT_EQ(one.criterion3, 0u);
  // Converged to two: no criterion 1; criterion 2 takes the lower fitness of those two.
  Predictions two = predict({pair(converged, 0.05), pair(iterations, 0.01),
                             pair(RegistrationState::kRelMse, 0.03)});
  EXPECT_FALSE(two.criterion1);
  EXPECT_EQ(two.criterion2, 2u);
  EXPECT_EQ(two.criterion3, 1u);
  // Converged to none: only criterion 3.
  Predictions none = predict({pair(iterations, 0.05), pair(RegistrationState::kNoCorrespondences, 0.04)});
  EXPECT_FALSE(none.criterion1);
  EXPECT_FALSE(none.criterion2);
  EXPECT_EQ(none.criterion3, 1u);
  // Registrations that did not run have no fitness and predict nothing.
  Predictions small = predict({PairResult(), PairResult()});
  EXPECT_FALSE(small.criterion1 || small.criterion2 || small.criterion3);
}

}  // namespace
}  // namespace granular
