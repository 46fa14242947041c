// The L-shape search (Zhang et al. 2017): its three criteria and the heading search.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "granular_core/cuboids/lshape.h"

namespace granular {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Exact points: the paper's d0 of 1 cm (the default's 10 cm is for a real sensor's noise).
LShapeConfig withCriterion(LShapeCriterion criterion) {
  LShapeConfig config;
  config.criterion = criterion;
  config.closeness_d0 = 0.01;
  return config;
}

// The two faces of a 4.5 x 1.8 m rectangle turned by `yaw` that meet at its corner (-L/2, -W/2),
// a point every 5 cm, around `centre`; with `all_faces`, its whole outline.
std::vector<Eigen::Vector2d> lShape(double yaw, const Eigen::Vector2d& centre,
                                    bool all_faces = false) {
  const Eigen::Rotation2Dd turn(yaw);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i <= 90; ++i) {
    points.push_back(centre + turn * Eigen::Vector2d(-2.25 + 0.05 * i, -0.9));
    if (all_faces) {
      points.push_back(centre + turn * Eigen::Vector2d(-2.25 + 0.05 * i, 0.9));
    }
  }
  for (int i = 1; i <= 36; ++i) {
    points.push_back(centre + turn * Eigen::Vector2d(-2.25, -0.9 + 0.05 * i));
    if (all_faces && i < 36) {
      points.push_back(centre + turn * Eigen::Vector2d(2.25, -0.9 + 0.05 * i));
    }
  }
  return points;
}

TEST(LShapeScoreTest, ThreeCornerPointsScoreAsThePaperDefinesEachCriterion) {
  const std::vector<Eigen::Vector2d> points = {{0, 0}, {1, 0}, {0, 1}};
  // Area: minus the enclosing rectangle's area.
  EXPECT_DOUBLE_EQ(lshapeScore(points, 0.0, withCriterion(LShapeCriterion::kArea)), -1.0);
  // Closeness: every point lies on one of the nearer edges (x = 0, y = 0), so each counts
  // 1 / d0.
  EXPECT_DOUBLE_EQ(lshapeScore(points, 0.0, withCriterion(LShapeCriterion::kCloseness)), 300.0);
  // Variance: (1, 0) is nearer the edge y = 0 (distance 0), (0, 1) the edge x = 0 (0), and
  // (0, 0) is as near both: each set is one distance, of no variance.
  EXPECT_DOUBLE_EQ(lshapeScore(points, 0.0, withCriterion(LShapeCriterion::kVariance)), 0.0);
  // At 45 degrees the rectangle is sqrt(2)/2 by sqrt(2): area 1.
  EXPECT_NEAR(lshapeScore(points, M_PI / 4, withCriterion(LShapeCriterion::kArea)), -1.0, 1e-12);
}

TEST(LShapeScoreTest, TheClosenessFloorIsD0) {
  LShapeConfig config = withCriterion(LShapeCriterion::kCloseness);
  config.closeness_d0 = 0.5;
  // (0.2, 0.2) is 0.2 from both nearer edges: it counts 1 / 0.5.
  const std::vector<Eigen::Vector2d> points = {{0, 0}, {1, 0}, {0, 1}, {0.2, 0.2}};
  EXPECT_DOUBLE_EQ(lshapeScore(points, 0.0, config), 4 * 2.0);
}

TEST(LShapeFitTest, EachCriterionFindsTheHeadingOfAnLShape) {
  for (const LShapeCriterion criterion :
       {LShapeCriterion::kArea, LShapeCriterion::kCloseness, LShapeCriterion::kVariance}) {
    for (const double yaw_deg : {0.0, 17.33, 44.9, 71.26, 89.95, 123.4}) {
      const LShapeConfig config = withCriterion(criterion);
      // An L's hull is a right triangle, whose rectangle along the hypotenuse has the same area
      // as the one along its legs: the area criterion needs the whole outline.
      const bool all_faces = criterion == LShapeCriterion::kArea;
      const AxisRectangle rectangle =
          fitLShape(lShape(yaw_deg * kDeg, {15.0, -3.0}, all_faces), config);
      const double error = std::remainder(rectangle.heading - yaw_deg * kDeg, M_PI / 2);
      // Closeness ties within 0.13 deg: the 4.5 m face's far end then lies within d0 (1 cm)
      // of its edge.
      EXPECT_LT(std::abs(error) / kDeg, 0.15)
          << config::enumName(criterion) << " at " << yaw_deg << " deg";
      EXPECT_GE(rectangle.heading, 0.0);
      EXPECT_LT(rectangle.heading, M_PI / 2);
      // The rectangle encloses the L: 4.5 by 1.8 m, in one order or the other.
      const Eigen::Vector2d extent = rectangle.extent();
      EXPECT_NEAR(extent.maxCoeff(), 4.5, 0.01);
      EXPECT_NEAR(extent.minCoeff(), 1.8, 0.01);
      EXPECT_LT((rectangle.centre() - Eigen::Vector2d(15.0, -3.0)).norm(), 0.01);
    }
  }
}

TEST(LShapeFitTest, TheFineSearchRefinesTheCoarseScan) {
  LShapeConfig coarse_only = withCriterion(LShapeCriterion::kVariance);
  coarse_only.fine_step_deg = coarse_only.coarse_step_deg;
  const std::vector<Eigen::Vector2d> points = lShape(17.33 * kDeg, {0, 0});
  EXPECT_NEAR(fitLShape(points, coarse_only).heading / kDeg, 17.0, 1e-9);
  EXPECT_NEAR(fitLShape(points, withCriterion(LShapeCriterion::kVariance)).heading / kDeg, 17.3,
              1e-9);
}

TEST(LShapeFitTest, NoPointsIsAnError) {
  EXPECT_THROW(fitLShape({}, LShapeConfig()), std::invalid_argument);
}

TEST(ThinnedPointsTest, PointsOfOneCellBecomeTheirMean) {
  const std::vector<Eigen::Vector2d> points = {
      {0.01, 0.01}, {0.03, 0.02}, {0.12, 0.01}, {-0.01, 0.01}};
  std::vector<Eigen::Vector2d> thinned = thinnedPoints(points, 0.05);
  ASSERT_EQ(thinned.size(), 3u);
  std::sort(thinned.begin(), thinned.end(),
            [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
  EXPECT_EQ(thinned[0], Eigen::Vector2d(-0.01, 0.01));
  EXPECT_NEAR((thinned[1] - Eigen::Vector2d(0.02, 0.015)).norm(), 0.0, 1e-12);
  EXPECT_EQ(thinned[2], Eigen::Vector2d(0.12, 0.01));
  EXPECT_TRUE(thinnedPoints({}, 0.05).empty());
  EXPECT_THROW(thinnedPoints(points, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace granular
