// ICP-NL (icp_nl.cpp: PCL's loop with the analytic Levenberg-Marquardt step): it undoes a
// known rigid motion and says whether it converged.
#include <gtest/gtest.h>

#include "granular_core/registration/registration.h"
#include "support/known_motion.h"

namespace granular {
namespace {
using testing_support::convergingIcp;
using testing_support::KnownMotion;

TEST(IcpNlTest, UndoesAKnownRigidMotionAndConverges) {
  const KnownMotion scene;
  const IcpClassifierConfig config = convergingIcp();
  const PairResult result = scene.aligned(prepareIcpNl, config);
  EXPECT_TRUE(result.converged()) << registrationStateName(result.state);
  EXPECT_GT(result.iterations, 1);
  EXPECT_LT(result.iterations, config.max_iterations);
  EXPECT_LT(scene.residual(result.transform), 1e-3);  // m, at the box's corners
}

TEST(IcpNlTest, StoppedByTheIterationLimitIsNotConvergence) {
  const KnownMotion scene;
  IcpClassifierConfig config = convergingIcp();
  config.max_iterations = 1;
  const PairResult result = scene.aligned(prepareIcpNl, config);
  EXPECT_EQ(result.state, RegistrationState::kIterations);
  EXPECT_EQ(result.iterations, 1);
  EXPECT_GT(scene.residual(result.transform), 1e-3);  // one step is not enough
}

TEST(IcpNlTest, ASourceOutOfReachHasNoCorrespondences) {
  const KnownMotion scene(Eigen::Vector3f(10.0f, 0.0f, 0.0f));
  const IcpClassifierConfig config = convergingIcp();
  const PairResult result = scene.aligned(prepareIcpNl, config);
  EXPECT_EQ(result.state, RegistrationState::kNoCorrespondences);
  EXPECT_FALSE(result.converged());
}

}  // namespace
}  // namespace granular
