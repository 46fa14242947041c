// The ground stage on synthetic scenes with exact answers: a tilted plane with obstacles on it.
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/ground/ground.h"
#include "support/tilted_road.h"

namespace granular {
namespace {
using testing_support::kDeg;
using testing_support::TiltedRoadTest;

TEST_F(TiltedRoadTest, ExactlyTheObstaclePointsStandAboveTheGround) {
  for (const GroundModel model : {GroundModel::kPlane, GroundModel::kLines}) {
    SCOPED_TRACE(config::enumName(model));
    GroundConfig config;
    config.model = model;
    config.plane.sensor_height = kSensorHeight;
    config.plane.seed_half_fov_deg = 180.0;
    const GroundEstimate estimate = estimateGround(cloud_, config);
    ASSERT_EQ(estimate.ground.size(), cloud_.size());
    std::size_t wrong = 0;
    for (std::size_t i = 0; i < cloud_.size(); ++i) {
      wrong += estimate.ground[i] != (i < road_end_);
    }
    EXPECT_EQ(wrong, 0u);
  }
}

TEST_F(TiltedRoadTest, LevellingPutsTheRoadAtZeroAndKeepsHeights) {
  GroundPlaneConfig config;
  config.sensor_height = kSensorHeight;
  config.seed_half_fov_deg = 180.0;
  const GroundPlane plane = estimateGroundPlane(cloud_, config);
  const Eigen::Isometry3d levelling = plane.levelling();
  for (std::size_t i = 0; i < cloud_.size(); i += 97) {
    const Eigen::Vector3d p = cloud_[i].getVector3fMap().cast<double>();
    EXPECT_NEAR((levelling * p).z(), plane.heightOf(p), 1e-9);
  }
  EXPECT_NEAR((levelling.linear() * plane.normal - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
}

TEST(GroundTest, ANonFinitePointHasNoHeightAndIsNotGround) {
  Cloud cloud;
  cloud.push_back(PointXYZIT(NAN, 1.0f, -1.7f, 0, 0.0));
  cloud.push_back(PointXYZIT(5.0f, 1.0f, -1.73f, 0, 0.0));
  const GroundEstimate estimate = estimateGround(cloud);
  EXPECT_TRUE(std::isnan(estimate.heights[0]));
  EXPECT_FALSE(estimate.ground[0]);
  EXPECT_TRUE(estimate.ground[1]);
}

// The warning a run gives a frame without ground names why: no points, none finite, or no
// plane among them (with the lowest point, for a cloud in another frame); a found plane none.
TEST(GroundTest, AFrameWithoutGroundIsToldWhy) {
  GroundPlaneConfig config;
  config.sensor_height = 2.3;
  Cloud cloud;
  EXPECT_EQ(groundNotFound(cloud, 0, config), "no points, so no ground");
  cloud.push_back(PointXYZIT(NAN, 1.0f, -2.3f, 0, 0.0));
  cloud.push_back(PointXYZIT(1.0f, INFINITY, -2.3f, 0, 0.0));
  EXPECT_EQ(groundNotFound(cloud, 0, config), "all 2 points are NaN or infinite, so no ground");
  cloud.push_back(PointXYZIT(3.0f, 0.0f, -52.25f, 0, 0.0));
  const std::optional<std::string> why = groundNotFound(cloud, 0, config);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("no ground plane found among 1 points (the lowest at z = -52.25 m; road "
                      "is sought near z = -2.30 m"),
            std::string::npos)
      << *why;
  EXPECT_FALSE(groundNotFound(cloud, 40, config));
}

// A road every 0.4 m out to 40 m whose z straight under the sensor is `z0`, leaning by
// `tilt_deg` about the y axis (downhill ahead).
Cloud roadAt(double z0, double tilt_deg) {
  Cloud cloud;
  for (double x = -40.0; x <= 40.0; x += 0.4) {
    for (double y = -40.0; y <= 40.0; y += 0.4) {
      const double z = z0 - x * std::tan(tilt_deg * kDeg);
      cloud.push_back(PointXYZIT(static_cast<float>(x), static_cast<float>(y),
                                 static_cast<float>(z), 0, 0.0));
    }
  }
  return cloud;
}

GroundCheck checkRoad(const Cloud& cloud, const GroundConfig& config) {
  const GroundEstimate estimate = estimateGround(cloud, config);
  return checkGround(cloud, estimate.plane, estimate.inliers, config, "map");
}

// A cloud in a world frame: its road 50 m below the sensor, at the sensor's height (z = 0), or
// leaning 15 deg is named with the frame and the remedies; a road where the sensor file puts
// it is not, and a wall filling the view is a frame without ground, not another frame.
TEST(GroundTest, ARoadWhereTheSensorsFrameCannotHaveItIsNamed) {
  GroundConfig config;
  config.plane.sensor_height = 1.8;
  EXPECT_EQ(checkRoad(roadAt(-1.8, 0.0), config).verdict, GroundCheck::Verdict::kGround);
  EXPECT_EQ(checkRoad(roadAt(-2.5, 5.0), config).verdict, GroundCheck::Verdict::kGround);

  const GroundCheck below = checkRoad(roadAt(-51.8, 0.0), config);
  EXPECT_EQ(below.verdict, GroundCheck::Verdict::kNotSensorFrame);
  EXPECT_EQ(below.problem.find("the road lies at z = -51.80 m under the sensor, tilted 0.0 deg, "
                               "where the sensor's frame has it at z = -1.80 m"),
            0u)
      << below.problem;
  EXPECT_NE(below.problem.find("the cloud, in frame 'map', looks like a world or vehicle frame"),
            std::string::npos);
  EXPECT_NE(below.problem.find("static transform from 'map'"), std::string::npos);
  EXPECT_NE(below.problem.find("--sensor auto"), std::string::npos);

  const GroundCheck world = checkRoad(roadAt(0.0, 0.0), config);
  EXPECT_EQ(world.verdict, GroundCheck::Verdict::kNotSensorFrame);
  EXPECT_EQ(world.problem.find("the road lies at z = 0.00 m under the sensor"), 0u)
      << world.problem;

  const GroundCheck tilted = checkRoad(roadAt(-1.8, 15.0), config);
  EXPECT_EQ(tilted.verdict, GroundCheck::Verdict::kNotSensorFrame);
  EXPECT_EQ(tilted.problem.find("the road lies at z = -1.80 m under the sensor, tilted 15.0 deg"),
            0u)
      << tilted.problem;

  // Tolerances the user widened: the ground stage's own (RANSAC) and the check's.
  config.plane.eps_angle_deg = 20.0;
  config.sensor_frame.max_tilt_deg = 20.0;
  EXPECT_EQ(checkRoad(roadAt(-1.8, 15.0), config).verdict, GroundCheck::Verdict::kGround);

  Cloud wall;
  for (double y = -10.0; y <= 10.0; y += 0.05) {
    for (double z = -1.8; z <= 5.0; z += 0.05) {
      wall.push_back(PointXYZIT(3.0f, static_cast<float>(y), static_cast<float>(z), 0, 0.0));
    }
  }
  const GroundCheck walled = checkRoad(wall, GroundConfig());
  EXPECT_EQ(walled.verdict, GroundCheck::Verdict::kNotFound) << walled.problem;
}

TEST(GroundTest, ValidateNamesTheField) {
  const auto expectRefused = [](const std::function<void(GroundConfig&)>& change,
                                const std::string& named) {
    GroundConfig config;
    change(config);
    try {
      validate(config);
      ADD_FAILURE() << "accepted a config that should name " << named;
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find(named), std::string::npos) << error.what();
    }
  };
  // PCL's default, which would turn the constraint off.
  expectRefused([](GroundConfig& c) { c.plane.eps_angle_deg = 0.0; }, "plane.eps_angle_deg");
  // Grids too big for memory: a millimetre seed cell was a bare std::bad_alloc, a 1e30 m seed
  // range a crash.
  expectRefused([](GroundConfig& c) { c.plane.seed_cell = 1e-3; }, "plane.seed_cell");
  expectRefused([](GroundConfig& c) { c.plane.seed_max_range = 1e30; }, "plane.seed_max_range");
  expectRefused([](GroundConfig& c) { c.plane.refine_cell = 1e-9; }, "plane.refine_cell");
  expectRefused([](GroundConfig& c) { c.lines.bin_size = 1e-5; }, "lines.bin_size");
  expectRefused([](GroundConfig& c) { c.lines.max_range = 1e20; }, "lines.max_range");
}

}  // namespace
}  // namespace granular
