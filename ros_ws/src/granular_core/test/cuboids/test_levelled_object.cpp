// What the geometric and model fitters share (levelled_object.h): the object levelled on its
// ground within the height band, its outline, extents, the length axis, the rectangle grown
// from the seen corner and the box back in the sensor frame, on hand-made points.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "cuboids/levelled_object.h"

namespace granular {
namespace {
using cuboids::LevelledObject;

// The road 1.7 m below the sensor, level.
GroundPlane road() {
  GroundPlane plane;
  plane.offset = 1.7;
  return plane;
}

TEST(LevelObjectTest, KeepsThePointsWithinTheHeightBandAboveItsGround) {
  ObjectView view;
  view.ground = road();
  for (const double height : {0.1, 0.5, 1.0, 1.5, 5.0}) {  // 0.1: road; 5.0: above 4.5 m
    view.points.emplace_back(10.0 + height, 3.0, height - 1.7);
  }
  const std::optional<LevelledObject> object = cuboids::levelObject(view, ObjectPointsConfig());
  ASSERT_TRUE(object);
  ASSERT_EQ(object->points.size(), 3u);
  EXPECT_NEAR(object->points[0].z(), 0.5, 1e-12);
  EXPECT_NEAR(object->points[2].z(), 1.5, 1e-12);
  EXPECT_NEAR(object->top, 1.5, 1e-12);
  EXPECT_NEAR(object->range, std::hypot(10.5, 3.0), 1e-12);  // the nearest kept point
  EXPECT_NEAR(object->sensor.norm(), 0.0, 1e-12);

  ObjectPointsConfig more;
  more.min_points = 4;
  EXPECT_FALSE(cuboids::levelObject(view, more));
}

TEST(LevelObjectTest, WithoutAGroundTheLowestPointIsTheRoad) {
  ObjectView view;
  for (const double z : {-1.2, -0.2, 0.8}) {
    view.points.emplace_back(5.0, 0.0, z);
  }
  view.points.emplace_back(NAN, 0.0, -9.0);  // not finite: neither the road nor a point
  const std::optional<LevelledObject> object = cuboids::levelObject(view, ObjectPointsConfig());
  ASSERT_TRUE(object);
  ASSERT_EQ(object->points.size(), 3u);
  EXPECT_NEAR(object->points[0].z(), 0.0, 1e-12);  // kept: min_height does not apply
  EXPECT_NEAR(object->top, 2.0, 1e-12);
}

TEST(LevelObjectTest, AFewPointsOverAGapAreAnOverhangAndLeftOut) {
  // 100 points of a body up to 1.5 m, and a branch 1.5 m above it.
  ObjectView view;
  view.ground = road();
  for (int i = 0; i < 100; ++i) {
    view.points.emplace_back(8.0 + 0.04 * i, 0.0, 0.4 + 0.011 * i - 1.7);
  }
  std::vector<Eigen::Vector3d> branch = {{9.0, 0.0, 3.0 - 1.7}, {9.5, 0.0, 3.1 - 1.7}};
  ObjectView with_branch = view;
  with_branch.points.insert(with_branch.points.end(), branch.begin(), branch.end());
  std::optional<LevelledObject> object = cuboids::levelObject(with_branch, ObjectPointsConfig());
  ASSERT_TRUE(object);
  EXPECT_EQ(object->points.size(), 100u);
  EXPECT_NEAR(object->top, 0.4 + 0.011 * 99, 1e-9);
  // Ten such points are more than overhang_share (5%) of the object: a roof, kept.
  for (int i = 0; i < 4; ++i) {
    with_branch.points.insert(with_branch.points.end(), branch.begin(), branch.end());
  }
  object = cuboids::levelObject(with_branch, ObjectPointsConfig());
  ASSERT_TRUE(object);
  EXPECT_EQ(object->points.size(), 110u);
  EXPECT_NEAR(object->top, 3.1, 1e-9);
}

TEST(LevelledObjectTest, SpanAtIsTheLargerOfMetresAndWhatTheAngleSpans) {
  EXPECT_DOUBLE_EQ(cuboids::spanAt(10.0, 0.3, 1.5), 0.3);
  EXPECT_DOUBLE_EQ(cuboids::spanAt(40.0, 0.3, 1.5), 40.0 * std::tan(1.5 * M_PI / 180.0));
}

TEST(LevelledObjectTest, TheOutlineKeepsTheNearestPointOfEachBearing) {
  // Two bearings 10 degrees apart, two points on each at 5 and 7 m.
  const double a = 0.5 * M_PI / 180.0, b = 10.5 * M_PI / 180.0;
  const std::vector<Eigen::Vector2d> points = {
      7.0 * Eigen::Vector2d(std::cos(a), std::sin(a)),
      5.0 * Eigen::Vector2d(std::cos(b), std::sin(b)),
      5.0 * Eigen::Vector2d(std::cos(a), std::sin(a)),
      7.0 * Eigen::Vector2d(std::cos(b), std::sin(b))};
  const std::vector<Eigen::Vector2d> outline =
      cuboids::outline(points, Eigen::Vector2d::Zero(), 1.0);
  ASSERT_EQ(outline.size(), 2u);
  EXPECT_EQ(outline[0], points[2]);
  EXPECT_EQ(outline[1], points[1]);
}

TEST(LevelledObjectTest, TheOutlineBehindTheSensorRunsFromMinusToPlus180Degrees) {
  // Either side of the seam behind the sensor, and one point ahead: by bearing, least first.
  const auto at = [](double range, double deg) {
    return Eigen::Vector2d(range * std::cos(deg * M_PI / 180.0),
                           range * std::sin(deg * M_PI / 180.0));
  };
  const std::vector<Eigen::Vector2d> points = {at(6.0, 179.5), at(8.0, 0.5), at(6.0, -179.5),
                                               at(7.0, 179.6)};
  const std::vector<Eigen::Vector2d> outline =
      cuboids::outline(points, Eigen::Vector2d::Zero(), 1.0);
  ASSERT_EQ(outline.size(), 3u);
  EXPECT_EQ(outline[0], points[2]);
  EXPECT_EQ(outline[1], points[1]);
  EXPECT_EQ(outline[2], points[0]);
}

TEST(LevelledObjectTest, TheBodyExtentLeavesOutWhatIsBelowAThirdOfTheTop) {
  LevelledObject object;
  object.points = {{0.0, 0.0, 0.2}, {4.0, 0.0, 0.2}, {1.0, 0.0, 1.0}, {3.0, 1.0, 1.2}};
  object.top = 1.2;
  AxisRectangle rectangle;  // heading 0: u is x, v is y
  rectangle.max = Eigen::Vector2d(4.0, 1.0);
  EXPECT_EQ(cuboids::bodyExtent(object, rectangle), Eigen::Vector2d(2.0, 1.0));
  EXPECT_EQ(cuboids::extentAbove(object, rectangle, 0.0), Eigen::Vector2d(4.0, 1.0));
  EXPECT_EQ(cuboids::extentAbove(object, rectangle, 2.0), rectangle.extent());  // none there
}

TEST(LevelledObjectTest, TheAcrossShortfallIsTwoMedianBearingStepsAtTheRange) {
  LevelledObject object;
  object.range = 10.0;
  for (const double z : {0.5, 1.0}) {  // one column: a single bearing
    object.points.emplace_back(10.0, 0.0, z);
  }
  EXPECT_EQ(cuboids::acrossShortfall(object), 0.0);
  // Two columns 0.02 rad apart.
  object.points = {{10.0 * std::cos(0.01), 10.0 * std::sin(0.01), 1.0},
                   {10.0 * std::cos(0.01), -10.0 * std::sin(0.01), 1.0}};
  EXPECT_NEAR(cuboids::acrossShortfall(object), 2.0 * 10.0 * std::tan(0.02), 1e-12);
}

TEST(LevelledObjectTest, TheLengthAxisFollowsTheRulesOfItsHeader) {
  const Eigen::Vector2d along_u(1.0, 0.0);  // the sensor looks along u
  // Longer than the width by more than the tolerance: a side, the length.
  EXPECT_EQ(cuboids::lengthAxis({1.0, 4.5}, 1.8, 0.3, along_u), 1);
  // Both as wide as the class: seen end on, the length is along the line of sight.
  EXPECT_EQ(cuboids::lengthAxis({1.7, 1.8}, 1.8, 0.3, along_u), 0);
  EXPECT_EQ(cuboids::lengthAxis({1.7, 1.8}, 1.8, 0.3, Eigen::Vector2d(0.0, 1.0)), 1);
  // One face as wide as the class: it is the front or rear, the other axis the length.
  EXPECT_EQ(cuboids::lengthAxis({1.0, 1.8}, 1.8, 0.3, along_u), 0);
  // Across the line of sight (v) a face looks 1.0 m wide, along it (u) 1.3 m: u is nearer the
  // class's 1.8 m width, so v is the length; unless v may be 0.7 m wider than seen (the scan's
  // shortfall), which brings it within 0.1 m of the width and makes u the length.
  EXPECT_EQ(cuboids::lengthAxis({1.3, 1.0}, 1.8, 0.3, along_u), 1);
  EXPECT_EQ(cuboids::lengthAxis({1.3, 1.0}, 1.8, 0.3, along_u, [] { return 0.7; }), 0);
}

TEST(LevelledObjectTest, ARectangleGrowsAwayFromTheSensorAndStopsShortOfSeenEmptySpace) {
  AxisRectangle seen;  // heading 0
  seen.min = Eigen::Vector2d(10.0, 0.0);
  seen.max = Eigen::Vector2d(13.0, 0.5);
  const Eigen::Vector2d sensor = Eigen::Vector2d::Zero();
  AxisRectangle grown = cuboids::grownFromSeenCorner(seen, sensor, 0, 4.5, 1.8);
  EXPECT_EQ(grown.min, seen.min);  // the corner nearer the sensor stays
  EXPECT_DOUBLE_EQ(grown.max.x(), 14.5);
  EXPECT_DOUBLE_EQ(grown.max.y(), 1.8);
  // Seen empty beyond x = 14.2: the side (3 m seen of 4.5) stops at the last probe before it.
  grown = cuboids::grownFromSeenCorner(seen, sensor, 0, 4.5, 1.8,
                                       [](const Eigen::Vector2d& p) { return p.x() > 14.2; });
  EXPECT_DOUBLE_EQ(grown.max.x(), 14.0);
  EXPECT_DOUBLE_EQ(grown.max.y(), 1.8);  // 0.5 m seen of 1.8: not probed
}

TEST(LevelledObjectTest, RefutedGrowthCountsThePlacesBeyondTheSeenRectangle) {
  AxisRectangle seen;  // heading 0: 1.8 m both ways, the sensor at its low corner's side
  seen.min = Eigen::Vector2d(10.0, 0.0);
  seen.max = Eigen::Vector2d(11.8, 1.8);
  const Eigen::Vector2d sensor = Eigen::Vector2d::Zero();
  const auto everywhere = [](const Eigen::Vector2d&) { return true; };
  // Grown to 4.5 m along x: places every 0.25 m from 0.125 m, those more than a step beyond the
  // seen ends counted: x 12.125 to 14.375 (10) by y 0.125 to 1.625 (7).
  EXPECT_EQ(cuboids::refutedGrowth(seen, sensor, 0, 4.5, 1.8, everywhere, 0.25), 70u);
  EXPECT_EQ(cuboids::refutedGrowth(seen, sensor, 1, 4.5, 1.8, everywhere, 0.25), 70u);
  // Something seen beyond x = 13: six columns of the growth along x, none along y.
  const auto beyond_13 = [](const Eigen::Vector2d& p) { return p.x() > 13.0; };
  EXPECT_EQ(cuboids::refutedGrowth(seen, sensor, 0, 4.5, 1.8, beyond_13, 0.25), 42u);
  EXPECT_EQ(cuboids::refutedGrowth(seen, sensor, 1, 4.5, 1.8, beyond_13, 0.25), 0u);
}

TEST(LevelledObjectTest, TheSensorBoxStandsOnTheGround) {
  const Eigen::Isometry3d levelling = road().levelling();
  const OrientedBox box =
      cuboids::sensorBox(levelling, Eigen::Vector2d(5.0, 2.0), 0.3, Eigen::Vector3d(4, 2, 1.5));
  EXPECT_NEAR((box.centre() - Eigen::Vector3d(5.0, 2.0, -1.7 + 0.75)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(box.yaw(), 0.3, 1e-12);
  EXPECT_EQ(box.size(), Eigen::Vector3d(4, 2, 1.5));
}

}  // namespace
}  // namespace granular
