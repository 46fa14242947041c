// buildClassModel: plain and ICP class models.
#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "granular_core/models/class_model.h"
#include "granular_core/models/concatenate.h"
#include "granular_core/models/filter_chain.h"
#include "support/model_clouds.h"

namespace granular {
namespace {
using testing_clouds::pointsOf;
using testing_clouds::kCarSize;
using testing_clouds::boxSurface;
using testing_clouds::shifted;

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
            pointsOf(applyFilterChain(model.raw, model.summary.filters)));
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

TEST(ClassModelTest, TheBandsTopFollowsTheClassesBoxesSoTallClassesKeepTheirRoofs) {
  std::mt19937 random(4);
  const Eigen::Vector3d bus(11.0, 2.5, 3.2);
  const ModelCloud a = boxSurface(bus, 4000, random);
  const ModelCloud b = boxSurface(bus, 4000, random);
  const ClassModel model = buildClassModel("Bus", {a, b}, ModelBuildConfig(), nullptr, {},
                                           std::vector<double>{3.2, 3.1, 3.25});
  ASSERT_TRUE(model.summary.filters.pass_through.max_z);
  EXPECT_NEAR(*model.summary.filters.pass_through.max_z, 1.05 * 3.25, 1e-12);
  double top = 0.0;
  for (const pcl::PointXYZ& point : model.model.points) {
    top = std::max(top, double(point.z));
  }
  EXPECT_GT(top, 3.1) << "the roof is kept";
  // Without box heights the objects' own highest points set it.
  const ClassModel from_points = buildClassModel("Bus", {a, b}, ModelBuildConfig());
  EXPECT_NEAR(*from_points.summary.filters.pass_through.max_z, 1.05 * 3.2, 0.01);
}

TEST(ClassModelTest, AFilterThatEmptiesTheModelIsNamed) {
  std::mt19937 random(5);
  ModelCloud sparse;  // points a metre apart: the radius filter keeps none
  for (int i = 0; i < 20; ++i) {
    sparse.push_back(pcl::PointXYZ(static_cast<float>(i), 0.0f, 1.0f));
  }
  const ClassModel model = buildClassModel("Bus", {sparse}, ModelBuildConfig());
  EXPECT_TRUE(model.model.empty());
  ASSERT_TRUE(model.summary.emptied_by);
  EXPECT_EQ(*model.summary.emptied_by, FilterStage::kRadiusOutlier);
}

}  // namespace
}  // namespace granular
