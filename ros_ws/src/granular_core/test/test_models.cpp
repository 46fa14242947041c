#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/models/build_models.h"
#include "granular_core/models/concatenate.h"
#include "granular_core/models/filter_chain.h"
#include "granular_core/models/icp_concatenate.h"
#include "granular_core/models/mesh.h"
#include "model_clouds.h"

namespace granular {
namespace {

using testing_clouds::boxSurface;
using testing_clouds::lattice;
using testing_clouds::shifted;
using testing_clouds::sphere;

const Eigen::Vector3d kCarSize(4.4, 1.8, 1.5);

std::vector<Eigen::Vector3f> pointsOf(const ModelCloud& cloud) {
  std::vector<Eigen::Vector3f> points;
  for (const pcl::PointXYZ& point : cloud.points) {
    points.push_back(point.getVector3fMap());
  }
  return points;
}

ModelCloud join(const ModelCloud& a, const ModelCloud& b) {
  ModelCloud both = a;
  both += b;
  return both;
}

// ---- concatenation -------------------------------------------------------------------------

TEST(ConcatenateTest, GivesTheUnionInOrder) {
  const ModelCloud a = lattice({0, 0, 0}, 1.0, 3, 1, 1);
  const ModelCloud b = lattice({0, 5, 1}, 0.5, 1, 2, 1);
  const ModelCloud both = concatenate({a, b});
  ASSERT_EQ(both.size(), 5u);
  const std::vector<Eigen::Vector3f> expected = {
      {0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 5, 1}, {0, 5.5f, 1}};
  EXPECT_EQ(pointsOf(both), expected);
  EXPECT_TRUE(concatenate({}).empty());
  EXPECT_EQ(pointsOf(concatenate({ModelCloud(), a})), pointsOf(a));
}

TEST(ConcatenateTest, ModelCloudDropsNonFinitePoints) {
  Cloud cloud;
  cloud.push_back(PointXYZIT(1, 2, 3, 7, 0.5));
  cloud.push_back(PointXYZIT(NAN, 2, 3, 7, 0.5));
  cloud.push_back(PointXYZIT(4, 5, INFINITY, 7, 0.5));
  std::size_t dropped = 0;
  const ModelCloud model = toModelCloud(cloud, &dropped);
  EXPECT_EQ(dropped, 2u);
  EXPECT_EQ(pointsOf(model), std::vector<Eigen::Vector3f>({{1, 2, 3}}));
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
  const ModelCloud kept = passThroughZ(cloud, PassThroughConfig());
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

// ---- config --------------------------------------------------------------------------------

TEST(ModelConfigTest, ClassOverridesReplaceOnlyTheirValues) {
  ModelBuildConfig config;
  EXPECT_NO_THROW(validate(config));
  EXPECT_EQ(config.filtersFor("Pedestrian"), config.filters);
  EXPECT_EQ(config.filtersFor("Van"), config.filters);
  const FilterChainConfig bus = config.filtersFor("SchoolBus");
  EXPECT_EQ(bus.pass_through.min_z, 0.2);
  EXPECT_GT(bus.pass_through.max_z, 3.1);
  EXPECT_LT(bus.voxel_grid.leaf_size, 0.1);
  EXPECT_EQ(bus.statistical_outlier, config.filters.statistical_outlier);
  EXPECT_EQ(config.filtersFor("Sedan").pass_through, config.filters.pass_through);

  config.filters.statistical_outlier.mean_k = 8;
  config.class_filters["Pedestrian"].order =
      std::vector<FilterStage>{FilterStage::kPassThrough, FilterStage::kVoxelGrid};
  EXPECT_EQ(config.filtersFor("SchoolBus").statistical_outlier.mean_k, 8);
  EXPECT_EQ(config.filtersFor("Pedestrian").order.size(), 2u);
}

TEST(ModelConfigTest, ValidateNamesTheField) {
  const auto message = [](const ModelBuildConfig& config) {
    try {
      validate(config);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  ModelBuildConfig config;
  config.filters.order.push_back(FilterStage::kVoxelGrid);
  EXPECT_NE(message(config).find("filters.order: stage voxel_grid is listed twice"),
            std::string::npos);
  config = ModelBuildConfig();
  config.class_filters["SUV"].min_z = 2.5;
  EXPECT_NE(message(config).find("class_filters.SUV: pass_through"), std::string::npos);
  config = ModelBuildConfig();
  config.filters.voxel_grid.leaf_size = 0.0;
  EXPECT_NE(message(config).find("voxel_grid.leaf_size"), std::string::npos);
  config = ModelBuildConfig();
  config.icp.max_fitness = -1.0;
  EXPECT_NE(message(config).find("icp.max_fitness"), std::string::npos);
}

// ---- class models --------------------------------------------------------------------------

TEST(ClassModelTest, AClassWithoutObjectsIsReported) {
  for (const ConcatenationMethod method :
       {ConcatenationMethod::kPlain, ConcatenationMethod::kIcp}) {
    ModelBuildConfig config;
    config.method = method;
    const ClassModel model = buildClassModel("Sedan", {}, config);
    EXPECT_EQ(model.summary.objects, 0u);
    EXPECT_EQ(model.summary.kept, 0u);
    EXPECT_TRUE(model.raw.empty());
    EXPECT_TRUE(model.model.empty());
    EXPECT_TRUE(model.summary.stages.empty());
    ASSERT_EQ(model.summary.warnings.size(), 1u);
    EXPECT_EQ(model.summary.warnings[0], "no objects of this class");
  }
}

TEST(ClassModelTest, PlainModelIsTheFilteredConcatenation) {
  std::mt19937 random(3);
  const ModelCloud a = boxSurface(kCarSize, 3000, random);
  const ModelCloud b = boxSurface(kCarSize, 2000, random);
  ModelBuildConfig config;
  const ClassModel model = buildClassModel("Sedan", {a, b}, config);
  EXPECT_EQ(model.summary.kept, 2u);
  EXPECT_EQ(model.summary.raw_points, 5000u);
  EXPECT_EQ(pointsOf(model.raw), pointsOf(concatenate({a, b})));
  EXPECT_EQ(pointsOf(model.model),
            pointsOf(applyFilterChain(model.raw, config.filtersFor("Sedan"))));
  ASSERT_EQ(model.summary.stages.size(), 4u);
  EXPECT_EQ(model.summary.stages.back().points, model.model.size());
}

TEST(ClassModelTest, IcpWithOneObjectWarnsAndUsesIt) {
  std::mt19937 random(5);
  const ModelCloud only = boxSurface(kCarSize, 500, random);
  ModelBuildConfig config;
  config.method = ConcatenationMethod::kIcp;
  const ClassModel model = buildClassModel("Jeep", {only}, config);
  EXPECT_EQ(model.summary.kept, 1u);
  EXPECT_EQ(model.summary.seed_objects, std::vector<std::size_t>{0});
  EXPECT_EQ(pointsOf(model.raw), pointsOf(only));
  ASSERT_FALSE(model.summary.warnings.empty());
  EXPECT_NE(model.summary.warnings[0].find("single object"), std::string::npos);
}

TEST(ClassModelTest, IcpAlignsShiftedViewsOntoTheSeed) {
  std::mt19937 random(9);
  const ModelCloud car = boxSurface(kCarSize, 6000, random);
  // Four one-sided views (the seed; the left one with the roof) and shifted, sparser whole
  // copies to align (sparser so that no copy outnumbers a view of its side).
  std::vector<ModelCloud> objects;
  for (const Side side : {Side::kFront, Side::kBack, Side::kLeft, Side::kRight}) {
    ModelCloud view;
    for (const pcl::PointXYZ& p : car.points) {
      const bool visible = side == Side::kFront  ? p.x > 2.19f
                           : side == Side::kBack ? p.x < -2.19f
                           : side == Side::kLeft ? p.y > 0.89f || p.z > 1.49f
                                                 : p.y < -0.89f;
      if (visible) {
        view.push_back(p);
      }
    }
    objects.push_back(view);
  }
  ModelCloud sparse;
  for (std::size_t i = 0; i < car.size(); i += 20) {
    sparse.push_back(car[i]);
  }
  objects.push_back(shifted(sparse, {0.15f, -0.1f, 0.0f}));
  objects.push_back(shifted(sparse, {-0.2f, 0.05f, 0.0f}));
  ModelBuildConfig config;
  config.method = ConcatenationMethod::kIcp;
  config.seed.objects_per_side = 1;
  const ClassModel model = buildClassModel("Sedan", objects, config);
  EXPECT_EQ(model.summary.seed_objects, (std::vector<std::size_t>{0, 1, 2, 3}));
  EXPECT_TRUE(model.summary.missing_sides.empty());
  EXPECT_EQ(model.summary.kept, 6u);
  EXPECT_EQ(model.summary.verdicts.at("kept"), 2u);
  // Every aligned point lies on the car's surface again.
  const Eigen::Vector3f half(2.2f, 0.9f, 0.0f);
  for (const pcl::PointXYZ& p : model.raw.points) {
    const float off_face = std::min({std::abs(std::abs(p.x) - half.x()),
                                     std::abs(std::abs(p.y) - half.y()), std::abs(p.z - 1.5f)});
    ASSERT_LT(off_face, 0.01f) << p;
  }
}

TEST(MeshTest, TriangulatesASurfaceAndToleratesTinyModels) {
  const ModelCloud plane = lattice({0, 0, 1}, 0.05, 20, 20, 1);
  const pcl::PolygonMesh mesh = triangulate(plane, MeshConfig());
  EXPECT_EQ(mesh.cloud.width * mesh.cloud.height, 400u);
  EXPECT_GT(mesh.polygons.size(), 300u);  // a full triangulation of the grid has 722
  EXPECT_TRUE(triangulate(ModelCloud(), MeshConfig()).polygons.empty());
}

}  // namespace
}  // namespace granular
