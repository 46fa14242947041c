// ICP (icp.cpp: PCL's loop with its SVD step): it undoes a known rigid motion and says whether
// it converged.
#include <gtest/gtest.h>

#include "granular_core/registration/registration.h"
#include "granular_core/registration/registration_classifier.h"
#include "support/known_motion.h"
#include "support/registration_scene.h"

namespace granular {
namespace {
using testing_clouds::shifted;
using testing_support::convergingIcp;
using testing_support::KnownMotion;
using testing_support::RegistrationTest;

TEST(IcpTest, UndoesAKnownRigidMotionAndConverges) {
  const KnownMotion scene;
  const IcpClassifierConfig config = convergingIcp();
  const PairResult result = scene.aligned(prepareIcp, config);
  EXPECT_TRUE(result.converged()) << registrationStateName(result.state);
  EXPECT_GT(result.iterations, 1);
  EXPECT_LT(result.iterations, config.max_iterations);
  EXPECT_LT(scene.residual(result.transform), 1e-3);  // m, at the box's corners
}

TEST(IcpTest, StoppedByTheIterationLimitIsNotConvergence) {
  const KnownMotion scene;
  IcpClassifierConfig config = convergingIcp();
  config.max_iterations = 1;
  const PairResult result = scene.aligned(prepareIcp, config);
  EXPECT_EQ(result.state, RegistrationState::kIterations);
  EXPECT_EQ(result.iterations, 1);
  EXPECT_GT(scene.residual(result.transform), 1e-3);  // one step is not enough
}

TEST(IcpTest, ASourceOutOfReachHasNoCorrespondences) {
  const KnownMotion scene(Eigen::Vector3f(10.0f, 0.0f, 0.0f));
  const IcpClassifierConfig config = convergingIcp();
  const PairResult result = scene.aligned(prepareIcp, config);
  EXPECT_EQ(result.state, RegistrationState::kNoCorrespondences);
  EXPECT_FALSE(result.converged());
}

TEST_F(RegistrationTest, IcpRecoversTheOffsetOfAView) {
  const RegistrationClassifier classifier(RegistrationMethod::kIcp, converging(), models_);
  const ModelCloud view = shifted(models_[0].cloud, Eigen::Vector3f(0.04f, -0.03f, 0.0f));
  const PairResult result = classifier.registerObjects({view})[0][0];
  ASSERT_TRUE(result.converged()) << registrationStateName(result.state);
  EXPECT_NEAR(result.transform(0, 3), -0.04, 0.01);
  EXPECT_NEAR(result.transform(1, 3), 0.03, 0.01);
  EXPECT_LT(result.fitness, 1e-4);
}

}  // namespace
}  // namespace granular
