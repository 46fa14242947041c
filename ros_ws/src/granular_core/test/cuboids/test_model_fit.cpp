// Model-based cuboid fitting: class models registered to a partial cloud from the L-shape's
// headings.
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/common/common.h>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "support/model_clouds.h"

namespace granular {
namespace {

using testing_clouds::boxSurface;
using testing_clouds::shifted;

constexpr double kSensorHeight = 1.73;
constexpr double kDeg = M_PI / 180.0;

// A car whose cabin sits behind its middle, so that its front and back differ: a 4.5 x 1.8 x
// 1.0 m body and a 2.5 x 1.6 x 0.5 m cabin on it, 0.6 m back. Object frame: road at z = 0.
ModelCloud car(std::size_t points, unsigned seed) {
  std::mt19937 random(seed);
  ModelCloud cloud = boxSurface({4.5, 1.8, 1.0}, points * 3 / 4, random);
  cloud += shifted(boxSurface({2.5, 1.6, 0.5}, points / 4, random), {-0.6f, 0.0f, 1.0f});
  return cloud;
}

ModelCloud van() {
  std::mt19937 random(7);
  return boxSurface({6.0, 2.1, 2.2}, 4000, random);
}

std::vector<LabelledModel> models() {
  std::vector<LabelledModel> result;
  result.push_back({"Van", van()});
  result.push_back({"Car", car(6000, 1)});
  return result;
}

// A fresh scan of the car at `centre` (road frame, x-y) turned by `yaw`: the half of its
// points facing the sensor, in the sensor frame (road 1.73 m below).
ObjectView scannedCar(const Eigen::Vector2d& centre, double yaw) {
  const Eigen::Vector2d sensor(0.0, 0.0);
  ObjectView object;
  object.ground = GroundPlane();
  object.ground->offset = kSensorHeight;
  const Eigen::Rotation2Dd turn(yaw);
  for (const pcl::PointXYZ& point : car(4000, 2)) {
    const Eigen::Vector2d xy = centre + turn * Eigen::Vector2d(point.x, point.y);
    if ((xy - centre).dot(sensor - centre) > 0.0) {
      object.points.emplace_back(xy.x(), xy.y(), point.z - kSensorHeight);
    }
  }
  return object;
}

// Degrees between the box's heading and `yaw`, all round (front and back differ).
double headingError(const OrientedBox& box, double yaw) {
  return std::abs(std::remainder(box.yaw() - yaw, 2 * M_PI)) / kDeg;
}

TEST(ModelFitTest, RecoversTheClassAndPoseOfAScannedModel) {
  const ModelCuboidFitter fitter(CuboidConfig(), models());
  // The model's own extent is the box: x and y of its points, z from the road to its top.
  const ModelCloud model = car(6000, 1);
  Eigen::Vector4f low, high;
  pcl::getMinMax3D(model, low, high);
  for (const double yaw_deg : {25.0, 115.0, 205.0, 295.0}) {
    const Eigen::Vector2d centre(12.0, 4.0);
    const std::optional<FittedCuboid> fitted = fitter.fit(scannedCar(centre, yaw_deg * kDeg));
    ASSERT_TRUE(fitted) << yaw_deg;
    EXPECT_EQ(fitted->label, "Car") << yaw_deg;
    EXPECT_LT(headingError(fitted->box, yaw_deg * kDeg), 1.0) << yaw_deg;
    // The model's box centre sits where the truth puts it (its x-y middle).
    const Eigen::Vector2d middle = Eigen::Rotation2Dd(yaw_deg * kDeg) *
                                   Eigen::Vector2d((low.x() + high.x()) / 2, (low.y() + high.y()) / 2);
    EXPECT_LT((fitted->box.centre().head<2>() - (centre + middle)).norm(), 0.05) << yaw_deg;
    EXPECT_NEAR(fitted->box.centre().z(), high.z() / 2 - kSensorHeight, 1e-6) << yaw_deg;
    EXPECT_NEAR(fitted->box.size().x(), high.x() - low.x(), 1e-6);
    EXPECT_NEAR(fitted->box.size().y(), high.y() - low.y(), 1e-6);
    EXPECT_NEAR(fitted->box.size().z(), high.z(), 1e-6);
    EXPECT_GT(fitted->score, 0.5) << yaw_deg;
    EXPECT_LE(fitted->score, 1.0);
  }
}

TEST(ModelFitTest, TwoHeadingsKeepTheGeometricLengthAxis) {
  CuboidConfig config;
  config.model.headings = 2;
  const ModelCuboidFitter fitter(config, models());
  const std::optional<FittedCuboid> fitted = fitter.fit(scannedCar({10.0, -6.0}, 200.0 * kDeg));
  ASSERT_TRUE(fitted);
  EXPECT_EQ(fitted->label, "Car");
  EXPECT_LT(headingError(fitted->box, 200.0 * kDeg), 1.0);
}

TEST(ModelFitTest, LabelsAreInLabelOrder) {
  EXPECT_EQ(ModelCuboidFitter(CuboidConfig(), models()).labels(),
            (std::vector<std::string>{"Car", "Van"}));
}

TEST(ModelFitTest, NoModelsOrAnEmptyOneIsAnError) {
  EXPECT_THROW(ModelCuboidFitter(CuboidConfig(), {}), std::invalid_argument);
  std::vector<LabelledModel> empty;
  empty.push_back({"Ghost", ModelCloud()});
  try {
    ModelCuboidFitter(CuboidConfig(), std::move(empty));
    FAIL() << "an empty model was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("Ghost"), std::string::npos) << error.what();
  }
}

TEST(ModelFitTest, MakeCuboidFitterFollowsTheMethod) {
  CuboidConfig config;
  config.method = CuboidMethod::kGeometric;
  const std::unique_ptr<CuboidFitter> geometric = makeCuboidFitter(config, {});
  const std::optional<FittedCuboid> fitted = geometric->fit(scannedCar({12.0, 4.0}, 0.3));
  ASSERT_TRUE(fitted);
  EXPECT_EQ(fitted->label, kUnknownLabel);
  config.method = CuboidMethod::kModel;
  EXPECT_EQ(makeCuboidFitter(config, models())->fit(scannedCar({12.0, 4.0}, 0.3))->label, "Car");
  EXPECT_THROW(makeCuboidFitter(config, {}), std::invalid_argument);
}

}  // namespace
}  // namespace granular
