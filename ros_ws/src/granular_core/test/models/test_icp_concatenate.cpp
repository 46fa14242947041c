// ICP concatenation and its seed.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "granular_core/models/concatenate.h"
#include "granular_core/models/icp_concatenate.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::kCarSize;
using testing_clouds::boxSurface;
using testing_clouds::lattice;
using testing_clouds::shifted;
using testing_clouds::sphere;

ModelCloud join(const ModelCloud& a, const ModelCloud& b) {
  ModelCloud both = a;
  both += b;
  return both;
}

// ---- ICP -----------------------------------------------------------------------------------

class IcpTest : public ::testing::Test {
 protected:
  static constexpr unsigned kSeed = 20240612;
  const ::testing::ScopedTrace trace_{__FILE__, __LINE__,
                                      "random seed " + std::to_string(kSeed)};
  std::mt19937 random_{kSeed};
  const ModelCloud model_ = boxSurface(kCarSize, 4000, random_);
};

TEST_F(IcpTest, RecoversTheShiftOfAShiftedCopyAndKeepsIt) {
  const ModelCloud object = shifted(model_, {0.2f, 0.1f, 0.0f});
  ModelCloud aligned;
  const Alignment alignment = alignToModel(object, model_, IcpConfig(), &aligned);
  EXPECT_EQ(alignment.verdict, IcpVerdict::kKept) << verdictName(alignment.verdict);
  EXPECT_TRUE(isConverged(alignment.convergence)) << convergenceName(alignment.convergence);
  constexpr float kCentimetre = 0.01f;  // required; ICP gets within ~1e-5 m here
  EXPECT_NEAR(alignment.transform(0, 3), -0.2f, kCentimetre);
  EXPECT_NEAR(alignment.transform(1, 3), -0.1f, kCentimetre);
  EXPECT_NEAR(alignment.transform(2, 3), 0.0f, kCentimetre);
  EXPECT_LT(alignment.rotation_deg, 0.1);
  EXPECT_LT(alignment.fitness, 1e-4);
  ASSERT_EQ(aligned.size(), model_.size());
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    ASSERT_LT((aligned[i].getVector3fMap() - model_[i].getVector3fMap()).norm(), kCentimetre)
        << "point " << i;
  }
}

TEST_F(IcpTest, DoesNotKeepAnotherShape) {
  const ModelCloud ball = sphere({0.0, 0.0, 0.75}, 0.9, 1000, random_);
  const Alignment alignment = alignToModel(ball, model_, IcpConfig());
  EXPECT_NE(alignment.verdict, IcpVerdict::kKept)
      << "fitness " << alignment.fitness << " m^2, moved " << alignment.translation << " m";
}

TEST_F(IcpTest, RunningOutOfIterationsIsNotConvergence) {
  IcpConfig config;
  config.max_iterations = 1;
  const Alignment alignment = alignToModel(shifted(model_, {0.2f, 0.1f, 0.0f}), model_, config);
  EXPECT_EQ(alignment.convergence, IcpConvergence::kIterations);
  EXPECT_EQ(alignment.verdict, IcpVerdict::kNotConverged);
}

TEST_F(IcpTest, RejectsTooFewPointsAndLargeCorrections) {
  const ModelCloud few = lattice({2.2, 0, 0.5}, 0.1, 1, 3, 3);  // 9 < min_points
  EXPECT_EQ(alignToModel(few, model_, IcpConfig()).verdict, IcpVerdict::kTooFewPoints);

  IcpConfig strict;
  strict.max_translation = 0.1;  // the shift below is 0.22 m
  EXPECT_EQ(alignToModel(shifted(model_, {0.2f, 0.1f, 0.0f}), model_, strict).verdict,
            IcpVerdict::kLargeCorrection);
}

TEST_F(IcpTest, ConcatenationKeepsAlignedObjectsOnly) {
  const ModelCloud object = shifted(model_, {0.2f, 0.1f, 0.0f});
  const ModelCloud ball = sphere({0.0, 0.0, 0.75}, 0.9, 1000, random_);
  IcpConfig config;
  config.target_leaf_size = 0.0;
  std::size_t calls = 0;
  const IcpConcatenation result =
      concatenateWithIcp({ball, object}, model_, {}, config, [&](std::size_t done, std::size_t n) {
        EXPECT_EQ(done, ++calls);
        EXPECT_EQ(n, 2u);
      });
  EXPECT_EQ(calls, 2u);
  EXPECT_EQ(result.kept, 1u);
  EXPECT_NE(result.alignments[0].verdict, IcpVerdict::kKept);
  EXPECT_EQ(result.alignments[1].verdict, IcpVerdict::kKept);
  ASSERT_EQ(result.model.size(), 2 * model_.size());
  for (std::size_t i = 0; i < model_.size(); ++i) {
    ASSERT_EQ(result.model[i].getVector3fMap(), model_[i].getVector3fMap());
    ASSERT_LT((result.model[model_.size() + i].getVector3fMap() - model_[i].getVector3fMap())
                  .norm(),
              0.01f);
  }
}

TEST_F(IcpTest, SeedObjectsAreKeptWithoutAlignment) {
  const IcpConcatenation result =
      concatenateWithIcp({model_, shifted(model_, {0.2f, 0.1f, 0.0f})}, model_, {0}, IcpConfig());
  EXPECT_EQ(result.kept, 2u);
  EXPECT_EQ(result.alignments[0].verdict, IcpVerdict::kKept);
  EXPECT_TRUE(result.alignments[0].transform.isIdentity());
  EXPECT_EQ(result.model.size(), 2 * model_.size());
}

// ---- seed selection ------------------------------------------------------------------------

TEST(SeedTest, SidesFollowTheCentroidOfTheVisibleFaces) {
  // Visible faces of a 4.4 x 1.8 car: front alone, front-left corner (more left than front once
  // scaled by the half extents), back, right.
  const ModelCloud front = lattice({2.2, -0.8, 0.1}, 0.1, 1, 17, 14);
  const ModelCloud front_left =
      join(lattice({2.2, -0.8, 0.1}, 0.1, 1, 17, 14), lattice({-2.1, 0.9, 0.1}, 0.1, 44, 1, 14));
  const ModelCloud back = lattice({-2.2, -0.8, 0.1}, 0.1, 1, 17, 14);
  const ModelCloud right = lattice({-2.1, -0.9, 0.1}, 0.1, 44, 1, 14);
  const Eigen::Vector2d half = halfExtents({front, front_left, back, right});
  EXPECT_NEAR(half.x(), 2.2, 1e-6);
  EXPECT_NEAR(half.y(), 0.9, 1e-6);
  EXPECT_EQ(sideSeen(front, half), Side::kFront);
  EXPECT_EQ(sideSeen(front_left, half), Side::kLeft);
  EXPECT_EQ(sideSeen(back, half), Side::kBack);
  EXPECT_EQ(sideSeen(right, half), Side::kRight);
}

TEST(SeedTest, PicksTheLargestObjectsOfEachSide) {
  const ModelCloud small_front = lattice({2.2, -0.4, 0.5}, 0.1, 1, 8, 5);
  const ModelCloud big_front = lattice({2.2, -0.8, 0.1}, 0.1, 1, 17, 14);
  const ModelCloud back = lattice({-2.2, -0.4, 0.5}, 0.1, 1, 8, 5);
  const ModelCloud left = lattice({-2.1, 0.9, 0.5}, 0.1, 40, 1, 5);
  const std::vector<ModelCloud> objects = {small_front, back, big_front, left};
  SeedConfig config;
  config.objects_per_side = 1;
  const SeedSelection one = selectSeedObjects(objects, config);
  EXPECT_EQ(one.indices, (std::vector<std::size_t>{2, 1, 3}));
  EXPECT_EQ(one.sides, (std::vector<Side>{Side::kFront, Side::kBack, Side::kLeft}));
  EXPECT_EQ(one.missing_sides, std::vector<Side>{Side::kRight});
  config.objects_per_side = 2;
  EXPECT_EQ(selectSeedObjects(objects, config).indices,
            (std::vector<std::size_t>{2, 0, 1, 3}));
}

}  // namespace
}  // namespace granular
