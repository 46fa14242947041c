// The filter chain: each stage exactly, and the chain in order.
#include <cmath>
#include <stdexcept>
#include <string>
#include <random>

#include <gtest/gtest.h>

#include "granular_core/models/filter_chain.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::pointsOf;
using testing_clouds::lattice;

ModelCloud join(const ModelCloud& a, const ModelCloud& b) {
  ModelCloud both = a;
  both += b;
  return both;
}

// ---- filters -------------------------------------------------------------------------------

TEST(FilterTest, PassThroughRemovesExactlyThePointsOutsideTheBand) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> body_z(0.25f, 1.95f), ground_z(-0.05f, 0.1999f),
      roof_z(2.0001f, 2.5f), xy(-2.0f, 2.0f);
  ModelCloud cloud, expected;
  for (int i = 0; i < 600; ++i) {
    const int kind = i % 6;  // 1 in 6 ground, 1 in 6 above the band
    const float z = kind == 0 ? ground_z(random) : kind == 1 ? roof_z(random) : body_z(random);
    const pcl::PointXYZ point(xy(random), xy(random), z);
    cloud.push_back(point);
    if (kind > 1) {
      expected.push_back(point);
    }
  }
  // The band is inclusive: 0.2f is just above 0.2 and 2.0f is 2.0.
  cloud.push_back(pcl::PointXYZ(0, 0, 0.2f));
  cloud.push_back(pcl::PointXYZ(0, 0, 2.0f));
  expected.push_back(pcl::PointXYZ(0, 0, 0.2f));
  expected.push_back(pcl::PointXYZ(0, 0, 2.0f));
  PassThroughConfig band;
  band.max_z = 2.0;  // the report's band, 0.2 to 2.0 m
  const ModelCloud kept = passThroughZ(cloud, band);
  EXPECT_EQ(kept.size(), 402u);
  EXPECT_EQ(pointsOf(kept), pointsOf(expected));
}

// A dense 1.0 x 0.5 x 0.5 m block (5 cm grid, 21 x 11 x 11 points) with six isolated points
// planted at least a metre from it and from each other.
class OutlierTest : public ::testing::Test {
 protected:
  const ModelCloud block_ = lattice({0.0, 0.0, 0.5}, 0.05, 21, 11, 11);
  const ModelCloud outliers_ = [] {
    ModelCloud planted;
    for (const Eigen::Vector3f& p : std::vector<Eigen::Vector3f>{
             {3, 0, 0.5}, {-2, 0, 0.5}, {0.5, 2.5, 1}, {0.5, -2, 1}, {0.5, 0.2, 2.5}, {3, 3, 3}}) {
      planted.push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
    }
    return planted;
  }();

  // The block with the outliers spread through it, as they would be in a concatenation.
  ModelCloud mixed() const {
    ModelCloud cloud;
    std::size_t next = 0;
    for (std::size_t i = 0; i < block_.size(); ++i) {
      cloud.push_back(block_[i]);
      if (i % 400 == 0 && next < outliers_.size()) {
        cloud.push_back(outliers_[next++]);
      }
    }
    return cloud;
  }
};

TEST_F(OutlierTest, RadiusRemovesExactlyThePlantedOutliers) {
  const ModelCloud kept = removeRadiusOutliers(mixed(), RadiusOutlierConfig());
  EXPECT_EQ(pointsOf(kept), pointsOf(block_));
}

TEST_F(OutlierTest, RadiusNeedsMinNeighborsOtherPoints) {
  // Two points 0.1 m apart: each has one neighbour within 0.2 m.
  const ModelCloud pair = lattice({0, 0, 1}, 0.1, 2, 1, 1);
  RadiusOutlierConfig config;
  config.min_neighbors = 1;
  EXPECT_EQ(removeRadiusOutliers(pair, config).size(), 2u);
  config.min_neighbors = 2;
  EXPECT_EQ(removeRadiusOutliers(pair, config).size(), 0u);
}

TEST_F(OutlierTest, StatisticalRemovesExactlyThePlantedOutliers) {
  // With K = 5 the block's points have a mean neighbour distance of 5.0 to 5.8 cm (corners);
  // the outliers' is over a metre, which lifts the threshold mean + 0.3 sigma above 7 cm.
  const ModelCloud kept = removeStatisticalOutliers(mixed(), StatisticalOutlierConfig());
  EXPECT_EQ(pointsOf(kept), pointsOf(block_));
}

TEST_F(OutlierTest, StatisticalLeavesTinyCloudsAlone) {
  // Four points, fewer than K + 1 = 6: no statistics, nothing removed.
  const ModelCloud tiny = join(lattice({0, 0, 1}, 0.1, 3, 1, 1), lattice({9, 9, 9}, 1, 1, 1, 1));
  EXPECT_EQ(removeStatisticalOutliers(tiny, StatisticalOutlierConfig()).size(), 4u);
}

TEST(FilterTest, VoxelGridGivesOnePointPerOccupiedVoxel) {
  // A 2 cm grid filling 1.0 x 0.5 x 0.3 m, no point nearer than 1 cm to a voxel face: the
  // 0.1 m grid has exactly 10 x 5 x 3 voxels, each point the centre of its voxel.
  const ModelCloud grid = lattice({0.01, 0.01, 0.01}, 0.02, 50, 25, 15);
  const ModelCloud voxels = voxelGrid(grid, VoxelGridConfig());
  ASSERT_EQ(voxels.size(), 150u);
  for (const pcl::PointXYZ& point : voxels.points) {
    for (int axis = 0; axis < 3; ++axis) {
      const float centre = std::floor(point.data[axis] / 0.1f) * 0.1f + 0.05f;
      EXPECT_NEAR(point.data[axis], centre, 1e-4f);
    }
  }
  // Random points in the same volume: at most one per voxel, and with ~130 points per voxel
  // every voxel is occupied.
  std::mt19937 random(11);
  std::uniform_real_distribution<float> x(0.0f, 0.999f), y(0.0f, 0.499f), z(0.0f, 0.299f);
  ModelCloud scattered;
  for (int i = 0; i < 20000; ++i) {
    scattered.push_back(pcl::PointXYZ(x(random), y(random), z(random)));
  }
  const std::size_t count = voxelGrid(scattered, VoxelGridConfig()).size();
  EXPECT_GE(count, 145u);
  EXPECT_LE(count, 150u);
}

TEST(FilterTest, ChainRunsTheStagesInOrderAndReportsEachCount) {
  ModelCloud cloud = lattice({0.01, 0.01, 0.01}, 0.02, 50, 25, 15);  // z 0.01 .. 0.29
  FilterChainConfig chain;
  chain.pass_through.max_z = 2.0;
  chain.order = {FilterStage::kVoxelGrid, FilterStage::kPassThrough};
  std::vector<StageResult> stages;
  const ModelCloud result = applyFilterChain(cloud, chain, &stages);
  ASSERT_EQ(stages.size(), 2u);
  EXPECT_EQ(stages[0].stage, FilterStage::kVoxelGrid);
  EXPECT_EQ(stages[0].points, 150u);
  EXPECT_EQ(stages[1].stage, FilterStage::kPassThrough);
  EXPECT_EQ(stages[1].points, 50u);  // voxel centres at z 0.25 only
  EXPECT_EQ(result.size(), 50u);

  chain.order.clear();
  EXPECT_EQ(applyFilterChain(cloud, chain).size(), cloud.size());

  stages.clear();
  chain = FilterChainConfig();
  EXPECT_TRUE(applyFilterChain(ModelCloud(), chain, &stages).empty());
  ASSERT_EQ(stages.size(), 4u);
  for (const StageResult& stage : stages) {
    EXPECT_EQ(stage.points, 0u);
  }
}

TEST(FilterTest, AVoxelTooSmallForTheCloudIsRefusedNotSkipped) {
  ModelCloud cloud;
  cloud.push_back(pcl::PointXYZ(0.0f, 0.0f, 0.0f));
  cloud.push_back(pcl::PointXYZ(4.0f, 2.0f, 1.5f));
  try {
    voxelGrid(cloud, VoxelGridConfig{1e-6});
    ADD_FAILURE() << "a 1 um voxel grid over metres was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("voxel_grid.leaf_size"), std::string::npos)
        << error.what();
  }
  EXPECT_EQ(voxelGrid(cloud, VoxelGridConfig{0.1}).size(), 2u);
}

}  // namespace
}  // namespace granular
