// Segmentation of scans without boxes: ground first, range-aware grid, gates, boxes.
#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/geometry/footprint.h"
#include "granular_core/segmentation/object_segmentation.h"
#include "support/road_scene.h"

namespace granular {
namespace {
using testing_support::addBox;
using testing_support::kSensorHeight;
using testing_support::road;
using testing_support::roadGround;

TEST(ObjectSegmentationTest, TwoBoxesThirtyCentimetresApartAreTwoSegments) {
  Cloud cloud = road();
  // Two cars nose to tail 10 m ahead, 0.3 m between them.
  const std::set<std::size_t> first = addBox(cloud, {8.0, 0.0}, 0.0, {4.0, 1.8, 1.5});
  const std::set<std::size_t> second = addBox(cloud, {12.3, 0.0}, 0.0, {4.0, 1.8, 1.5});
  const ObjectSegmentation result = segmentObjects(cloud, roadGround());
  ASSERT_EQ(result.segments.size(), 2u);
  EXPECT_EQ(std::set<std::size_t>(result.segments[0].indices.begin(),
                                  result.segments[0].indices.end()),
            first);
  EXPECT_EQ(std::set<std::size_t>(result.segments[1].indices.begin(),
                                  result.segments[1].indices.end()),
            second);
}

std::vector<std::set<std::size_t>> pointsOf(const ObjectSegmentation& result) {
  std::vector<std::set<std::size_t>> points;
  for (const Segment& segment : result.segments) {
    points.emplace_back(segment.indices.begin(), segment.indices.end());
  }
  return points;
}

TEST(ObjectSegmentationTest, OneSegmenterGivesEachFrameWhatAFreshOneGives) {
  // A grid of 640 cells a side (48 m at 0.15 m): its last column is the last bit of a row's
  // last word, where the first frame's car ends, 47.9 m ahead. The second frame's car stands
  // half a metre to the side of it: the first frame's cells must not be left occupied.
  ObjectSegmentationConfig config;
  config.max_range = 48.0;
  Cloud first = road();
  const std::set<std::size_t> edge_car = addBox(first, {46.0, 0.0}, 0.0, {3.8, 1.8, 1.5});
  Cloud second = road();
  const std::set<std::size_t> beside = addBox(second, {45.5, -0.6}, 0.0, {3.8, 1.8, 1.5});
  ObjectSegmenter segmenter(config);
  for (int pass = 0; pass < 2; ++pass) {
    const ObjectSegmentation at_edge =
        segmenter.segment(first, estimateGround(first, roadGround()));
    EXPECT_EQ(pointsOf(at_edge), std::vector<std::set<std::size_t>>{edge_car});
    const ObjectSegmentation next =
        segmenter.segment(second, estimateGround(second, roadGround()));
    EXPECT_EQ(pointsOf(next), std::vector<std::set<std::size_t>>{beside});
    EXPECT_EQ(pointsOf(next), pointsOf(segmentObjects(second, roadGround(), config)));
  }
}

TEST(ObjectSegmentationTest, AGroundedBoxGetsItsFootprintFromTheRoadToItsTop) {
  Cloud cloud = road();
  const double yaw = 0.4;
  addBox(cloud, {-9.0, 6.0}, yaw, {4.4, 1.8, 1.5});
  const ObjectSegmentation result = segmentObjects(cloud, roadGround());
  ASSERT_EQ(result.segments.size(), 1u);
  const OrientedBox& box = result.segments[0].box;
  EXPECT_NEAR(box.centre().x(), -9.0, 0.03);
  EXPECT_NEAR(box.centre().y(), 6.0, 0.03);
  EXPECT_NEAR(box.size().x(), 4.4, 0.03);
  EXPECT_NEAR(box.size().y(), 1.8, 0.03);
  EXPECT_NEAR(std::remainder(box.yaw() - yaw, M_PI), 0.0, 0.01);
  // From the road (not from the lowest return, 0.3 m up) to the top.
  EXPECT_NEAR(box.centre().z() - box.size().z() / 2, -kSensorHeight, 0.02);
  EXPECT_NEAR(box.centre().z() + box.size().z() / 2, -kSensorHeight + 1.5, 0.02);
}

TEST(ObjectSegmentationTest, WallsPolesAndKerbsAreGatedOutAndCounted) {
  Cloud cloud = road();
  addBox(cloud, {10.0, -4.0}, 0.0, {4.4, 1.8, 1.5});          // a car: kept
  addBox(cloud, {0.0, 12.0}, 0.0, {20.0, 0.3, 2.0});          // a long wall: too long
  addBox(cloud, {-6.0, -6.0}, 0.0, {9.0, 0.3, 1.2});          // a fence: the wall gate
  addBox(cloud, {6.0, 6.0}, 0.0, {0.25, 0.25, 4.0});          // a pole
  addBox(cloud, {-10.0, 3.0}, 0.0, {3.0, 0.2, 0.4});          // a kerb stone: too low
  ObjectSegmentationConfig config;
  config.walls.max_walls = 0;  // each gate once: nothing peeled off the walls
  const ObjectSegmentation result = segmentObjects(cloud, roadGround(), config);
  ASSERT_EQ(result.segments.size(), 1u);
  EXPECT_NEAR(result.segments[0].box.centre().x(), 10.0, 0.05);
  EXPECT_EQ(result.rejected.at("max_size"), 1u);
  EXPECT_EQ(result.rejected.at("wall"), 1u);
  EXPECT_EQ(result.rejected.at("pole"), 1u);
  EXPECT_EQ(result.rejected.at("min_top"), 1u);
}

TEST(ObjectSegmentationTest, ACarSeenOverAnothersRoofStandsWhereItsFootIsHidden) {
  // A car 12 m ahead seen above 1.2 m only: the car parked 8 m ahead, 1.5 m tall, hides the
  // rest from the sensor 1.73 m up.
  Cloud cloud = road();
  const std::set<std::size_t> front = addBox(cloud, {8.0, 0.0}, 0.0, {4.4, 1.8, 1.5});
  const std::set<std::size_t> behind =
      addBox(cloud, {12.5, 0.0}, 0.0, {1.8, 4.4, 1.6}, 0.05, 1.2);
  const ObjectSegmentation result = segmentObjects(cloud, roadGround());
  const std::vector<std::set<std::size_t>> found = pointsOf(result);
  EXPECT_EQ(std::set<std::set<std::size_t>>(found.begin(), found.end()),
            (std::set<std::set<std::size_t>>{front, behind}));

  // Alone, the same points float: a canopy or an awning, not standing on the road.
  Cloud alone = road();
  addBox(alone, {12.5, 0.0}, 0.0, {1.8, 4.4, 1.6}, 0.05, 1.2);
  const ObjectSegmentation floating = segmentObjects(alone, roadGround());
  EXPECT_TRUE(floating.segments.empty());
  EXPECT_EQ(floating.rejected.at("max_bottom"), 1u);

  // Taller than a car, a hidden foot does not make it stand: a hedge behind parked cars.
  Cloud hedge = road();
  addBox(hedge, {8.0, 0.0}, 0.0, {4.4, 1.8, 1.5});
  addBox(hedge, {12.5, 0.0}, 0.0, {1.8, 4.4, 2.6}, 0.05, 1.2);
  EXPECT_EQ(segmentObjects(hedge, roadGround()).segments.size(), 1u);
}

// The face turned to the sensor of a panel along x, at `y`, from `bottom` to `top` above the
// road, reaching down to 0.3 m within 0.5 m of each of `legs` (wheels, posts).
void addPanel(Cloud& cloud, double y, double length, double bottom, double top,
              const std::vector<double>& legs) {
  for (double u = -length / 2; u <= length / 2 + 1e-9; u += 0.05) {
    const bool leg = std::any_of(legs.begin(), legs.end(),
                                 [&](double at) { return std::abs(u - at) <= 0.5; });
    for (double h = leg ? 0.3 : bottom; h <= top + 1e-9; h += 0.05) {
      cloud.push_back(PointXYZIT(static_cast<float>(u), static_cast<float>(y),
                                 static_cast<float>(-kSensorHeight + h), 0, 0.0));
    }
  }
}

TEST(ObjectSegmentationTest, ABusSeenFromTheSideIsNoWall) {
  ObjectSegmentationConfig config;
  config.walls.max_walls = 0;  // the wall gate alone
  // A bus's side 8 m away, 11 m long: the body from 0.55 m to 3 m, its wheels to the road.
  Cloud bus = road();
  addPanel(bus, 8.0, 11.0, 0.55, 3.0, {-3.5, 3.5});
  const ObjectSegmentation kept = segmentObjects(bus, roadGround(), config);
  ASSERT_EQ(kept.segments.size(), 1u);
  EXPECT_NEAR(kept.segments[0].box.size().x(), 11.0, 0.1);
  EXPECT_EQ(kept.rejected.count("wall"), 0u);
  // The same panel standing on the road along its length is a wall ...
  Cloud wall = road();
  addPanel(wall, 8.0, 11.0, 0.3, 3.0, {});
  const ObjectSegmentation gated = segmentObjects(wall, roadGround(), config);
  EXPECT_TRUE(gated.segments.empty());
  EXPECT_EQ(gated.rejected.at("wall"), 1u);
  // ... and a guard rail on posts, raised but low, too.
  Cloud rail = road();
  addPanel(rail, 8.0, 11.0, 0.5, 0.8, {-3.5, 0.0, 3.5});
  EXPECT_EQ(segmentObjects(rail, roadGround(), config).rejected.at("wall"), 1u);
}

TEST(ObjectSegmentationTest, ATruckPassingBesideTheSensorIsOneSegmentAndTheOwnCarNone) {
  // A truck's side in the next lane, 2.2 m to the right, 7 m long: its middle comes nearer
  // than min_range (2.5 m). The sensor's own car returns its hood and mirrors within it.
  Cloud cloud = road();
  addPanel(cloud, -2.2, 7.0, 0.55, 3.0, {-2.5, 2.5});
  const std::size_t truck_points = cloud.size() - road().size();
  for (const Eigen::Vector2d& own : {Eigen::Vector2d(1.6, 0.6), Eigen::Vector2d(1.6, -0.6),
                                     Eigen::Vector2d(0.3, 1.05), Eigen::Vector2d(0.3, -1.05)}) {
    for (double h = 0.9; h <= 1.2; h += 0.05) {
      cloud.push_back(PointXYZIT(static_cast<float>(own.x()), static_cast<float>(own.y()),
                                 static_cast<float>(-kSensorHeight + h), 0, 0.0));
    }
  }
  const ObjectSegmentation kept = segmentObjects(cloud, roadGround());
  ASSERT_EQ(kept.segments.size(), 1u);
  EXPECT_EQ(kept.segments[0].indices.size(), truck_points);
  EXPECT_NEAR(kept.segments[0].box.size().x(), 7.0, 0.1);
  // Leaving out the whole circle, as before own_half_width, cuts the side in two.
  ObjectSegmentationConfig circle;
  circle.own_half_width = circle.min_range;
  EXPECT_EQ(segmentObjects(cloud, roadGround(), circle).segments.size(), 2u);
}

TEST(ObjectSegmentationTest, ACarParkedAgainstAWallIsFoundWhenTheWallIsPeeledOff) {
  for (const double yaw : {0.0, 0.5}) {
    Cloud cloud = road();
    const Eigen::Rotation2Dd turn(yaw);
    // A car 10 m ahead and, 0.15 m beyond its right side, the face of a wall 20 m long (the
    // sensor sees one face): one component, too long to be an object.
    const std::set<std::size_t> car =
        addBox(cloud, turn * Eigen::Vector2d(10.0, -4.0), yaw, {4.4, 1.8, 1.5});
    addBox(cloud, turn * Eigen::Vector2d(10.0, -5.05), yaw, {20.0, 0.0, 2.0});
    ObjectSegmentationConfig config;
    config.walls.max_walls = 0;
    const ObjectSegmentation merged = segmentObjects(cloud, roadGround(), config);
    EXPECT_TRUE(merged.segments.empty()) << "yaw " << yaw;
    EXPECT_EQ(merged.rejected.at("max_size"), 1u) << "yaw " << yaw;

    const ObjectSegmentation peeled = segmentObjects(cloud, roadGround());
    ASSERT_EQ(peeled.segments.size(), 1u) << "yaw " << yaw;
    EXPECT_EQ(peeled.rejected.at("walls_peeled"), 1u) << "yaw " << yaw;
    // The car's points, less its side against the wall (which a sensor would not see).
    const Segment& segment = peeled.segments[0];
    for (const std::size_t i : segment.indices) {
      EXPECT_EQ(car.count(i), 1u) << "yaw " << yaw << ": point " << i << " is the wall's";
    }
    EXPECT_GT(segment.indices.size(), car.size() * 6 / 10) << "yaw " << yaw;
    const Eigen::Vector2d centre = turn.inverse() * segment.box.centre().head<2>();
    EXPECT_NEAR(centre.x(), 10.0, 0.05) << "yaw " << yaw;
    EXPECT_NEAR(centre.y(), -4.0, 0.15) << "yaw " << yaw;
  }
}

TEST(ObjectSegmentationTest, ACarAndAHedgeJoinedOnlyByAVergeStayApart) {
  // A car 10 m ahead and, a metre beyond its right side, a hedge; between them a verge whose
  // returns stand 0.3 m above the road (below link_min_top), one every 0.1 m.
  Cloud cloud = road();
  const std::set<std::size_t> car = addBox(cloud, {10.0, -2.0}, 0.0, {4.2, 1.8, 1.5});
  const std::set<std::size_t> hedge = addBox(cloud, {10.0, -4.3}, 0.0, {4.0, 0.8, 1.6});
  for (double x = 8.0; x <= 12.0; x += 0.1) {
    for (double y = -2.95; y > -3.9; y -= 0.1) {
      cloud.push_back(PointXYZIT(static_cast<float>(x), static_cast<float>(y),
                                 static_cast<float>(-kSensorHeight + 0.3), 0, 0.0));
    }
  }
  const auto holding = [](const ObjectSegmentation& result, const std::set<std::size_t>& of) {
    std::set<std::size_t> segments;
    for (std::size_t s = 0; s < result.segments.size(); ++s) {
      for (const std::size_t i : result.segments[s].indices) {
        if (of.count(i) != 0) {
          segments.insert(s);
        }
      }
    }
    return segments;
  };
  const ObjectSegmentation apart = segmentObjects(cloud, roadGround());
  const std::set<std::size_t> with_car = holding(apart, car);
  const std::set<std::size_t> with_hedge = holding(apart, hedge);
  ASSERT_EQ(with_car.size(), 1u);
  ASSERT_EQ(with_hedge.size(), 1u);
  EXPECT_NE(*with_car.begin(), *with_hedge.begin());
  // The car's segment is the car, and the verge next to it at most.
  const OrientedBox& box = apart.segments[*with_car.begin()].box;
  EXPECT_NEAR(box.centre().x(), 10.0, 0.05);
  EXPECT_NEAR(box.centre().y(), -2.0, 0.3);

  ObjectSegmentationConfig config;
  config.link_min_top = 0.0;  // the verge links them: one segment
  const ObjectSegmentation joined = segmentObjects(cloud, roadGround(), config);
  EXPECT_EQ(holding(joined, car), holding(joined, hedge));
}

TEST(ObjectSegmentationTest, AWallAloneLeavesNoSegmentWhenPeeled) {
  Cloud cloud = road();
  addBox(cloud, {3.0, 9.0}, 0.3, {25.0, 0.2, 2.0});  // both faces: two walls 0.2 m apart
  const ObjectSegmentation result = segmentObjects(cloud, roadGround());
  EXPECT_TRUE(result.segments.empty());
  EXPECT_GE(result.rejected.at("walls_peeled"), 1u);
}

TEST(ObjectSegmentationTest, FarCellsJoinAcrossTheGapsBetweenReturns) {
  // A car side 35 m away seen by a LiDAR 0.5 deg between returns: 0.3 m gaps along it.
  Cloud cloud = road();
  const double range = 35.0;
  for (double azimuth = -0.06; azimuth <= 0.06; azimuth += 0.5 * M_PI / 180.0) {
    for (double h = 0.3; h <= 1.4; h += 0.1) {
      cloud.push_back(PointXYZIT(static_cast<float>(range), static_cast<float>(range * azimuth),
                                 static_cast<float>(-kSensorHeight + h), 0, 0.0));
    }
  }
  ObjectSegmentationConfig config;
  config.azimuth_step_deg = 0.5;
  ASSERT_EQ(segmentObjects(cloud, roadGround(), config).segments.size(), 1u);
  config.link_range_steps = 0.0;  // touching cells only: each of the 14 columns alone
  EXPECT_EQ(segmentObjects(cloud, roadGround(), config).segments.size(), 14u);
}

// A vertical face seen by a LiDAR `step_deg` between returns: one column of returns 0.3 m to
// 1.4 m above the road per azimuth, from `first` to `last` returns, each where the ray from
// the sensor meets the line from `from` to `to` (bird's-eye, metres).
void addScannedFace(Cloud& cloud, double step_deg, int first, int last,
                    const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
  for (int k = first; k <= last; ++k) {
    const double azimuth = k * step_deg * M_PI / 180.0;
    const Eigen::Vector2d ray(std::cos(azimuth), std::sin(azimuth));
    const Eigen::Vector2d along = to - from;
    // from + t along = s ray: solve for s, the range.
    const double range = (from.x() * along.y() - from.y() * along.x()) /
                         (ray.x() * along.y() - ray.y() * along.x());
    for (double h = 0.3; h <= 1.4; h += 0.1) {
      cloud.push_back(PointXYZIT(static_cast<float>(range * ray.x()),
                                 static_cast<float>(range * ray.y()),
                                 static_cast<float>(-kSensorHeight + h), 0, 0.0));
    }
  }
}

std::size_t segmentsOf(const Cloud& cloud, const ObjectSegmentationConfig& config) {
  return segmentObjects(cloud, roadGround(), config).segments.size();
}

TEST(ObjectSegmentationTest, ACellJoinsTheFartherCellWhoseLongerReachCoversThem) {
  // Two posts on the line of sight, three cells apart, either side of the range where the
  // link's reach steps from 2 cells to 3 (HDL-64E defaults: 3.3 returns' spacing, 0.176 deg,
  // 0.15 m cells: 29.6 m). The nearer one's reach (2) falls short, the farther one's (3)
  // covers the pair: one segment, however the grid is scanned.
  ObjectSegmentationConfig config;
  const double reach_per_m = config.link_range_steps * config.azimuth_step_deg * M_PI / 180.0 /
                             config.cell_size;
  // Cell centres: the grid's cells start at -max_range.
  const auto centre = [&](double at) {
    return -config.max_range +
           (std::floor((at + config.max_range) / config.cell_size) + 0.5) * config.cell_size;
  };
  const double x = centre(0.0), nearer = centre(29.55), farther = nearer + 3 * config.cell_size;
  ASSERT_EQ(std::ceil(reach_per_m * std::hypot(x, nearer)), 2.0);
  ASSERT_EQ(std::ceil(reach_per_m * std::hypot(x, farther)), 3.0);
  Cloud cloud = road();
  for (const double y : {nearer, farther}) {
    for (double h = 0.3; h <= 1.4; h += 0.1) {
      cloud.push_back(PointXYZIT(static_cast<float>(x), static_cast<float>(y),
                                 static_cast<float>(-kSensorHeight + h), 0, 0.0));
    }
  }
  EXPECT_EQ(segmentsOf(cloud, config), 1u);
  config.link_range_steps *= 0.9;  // both reaches 2 cells: two posts
  EXPECT_EQ(segmentsOf(cloud, config), 2u);
}

TEST(ObjectSegmentationTest, FarCarsSideBySideOnASparseLidarAreTwoSegments) {
  // The simulator's LiDAR, 1 deg between returns: the rears of two cars 30 m ahead, two
  // returns' spacing (1.05 m) between them across the line of sight.
  Cloud cloud = road();
  addScannedFace(cloud, 1.0, -3, 0, {30.0, -5.0}, {30.0, 5.0});
  addScannedFace(cloud, 1.0, 3, 6, {30.0, -5.0}, {30.0, 5.0});
  ObjectSegmentationConfig config;
  config.azimuth_step_deg = 1.0;
  EXPECT_EQ(segmentsOf(cloud, config), 2u);
  config.link_azimuth_steps = config.link_range_steps;  // across as far as along: one
  EXPECT_EQ(segmentsOf(cloud, config), 1u);
}

TEST(ObjectSegmentationTest, AFaceSeenAtASlantStaysOneSegment) {
  // A car's side 20 m away, 25 deg off the line of sight: its returns, 1 deg apart, lie
  // 0.35 m apart across the line of sight but 0.75 m apart along it.
  Cloud cloud = road();
  const double slant = 25.0 * M_PI / 180.0;
  const Eigen::Vector2d from(20.0, 0.0);
  addScannedFace(cloud, 1.0, 0, 5, from, from + 4.0 * Eigen::Vector2d(std::cos(slant),
                                                                     std::sin(slant)));
  ObjectSegmentationConfig config;
  config.azimuth_step_deg = 1.0;
  EXPECT_EQ(segmentsOf(cloud, config), 1u);
  config.link_range_steps = config.link_azimuth_steps;  // along only as far as across: split
  EXPECT_GT(segmentsOf(cloud, config), 1u);
}

TEST(ObjectSegmentationTest, AFilledFootprintGetsTheRectangleOfAllItsPoints) {
  // Irregular heaps seen from above, sparse to dense (many of their cells have cells of the
  // segment in all four quadrants around them, whose points the footprint's hull skips): each
  // box is the minimum-area rectangle of every one of its segment's points.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), fraction(0.0, 1.0);
  for (int heap = 0; heap < 40; ++heap) {
    Cloud cloud = road();
    const double yaw = M_PI * fraction(random);
    const double length = 1.0 + 3.0 * fraction(random), taper = fraction(random);
    const int points = 200 + static_cast<int>(3000 * fraction(random));
    for (int i = 0; i < points; ++i) {
      const double u = length * unit(random);
      const double v = unit(random) * (1.0 - taper * std::abs(u) / length);
      cloud.push_back(PointXYZIT(static_cast<float>(12.0 + u * std::cos(yaw) - v * std::sin(yaw)),
                                 static_cast<float>(-5.0 + u * std::sin(yaw) + v * std::cos(yaw)),
                                 static_cast<float>(-kSensorHeight + 0.3 + fraction(random)), 0,
                                 0.0));
    }
    const ObjectSegmentation result = segmentObjects(cloud, roadGround());
    ASSERT_FALSE(result.segments.empty()) << "heap " << heap;
    for (const Segment& segment : result.segments) {  // a sparse heap may come in parts
      std::vector<Eigen::Vector2d> xy;
      for (const std::size_t i : segment.indices) {
        xy.emplace_back(cloud[i].x, cloud[i].y);
      }
      const Rectangle all = minimumAreaRectangle(xy);
      EXPECT_DOUBLE_EQ(segment.box.centre().x(), all.centre.x()) << "heap " << heap;
      EXPECT_DOUBLE_EQ(segment.box.centre().y(), all.centre.y()) << "heap " << heap;
      EXPECT_NEAR(std::remainder(segment.box.yaw() - all.yaw, M_PI), 0.0, 1e-12);
      EXPECT_NEAR(segment.box.size().x(), all.length + 0.01, 1e-12);  // 5 mm edge allowance
      EXPECT_NEAR(segment.box.size().y(), all.width + 0.01, 1e-12);
    }
  }
}

TEST(ObjectSegmentationTest, ValidateNamesTheField) {
  ObjectSegmentationConfig config;
  config.gates.max_length = -1.0;
  try {
    validate(config);
    ADD_FAILURE() << "accepted a negative max_length";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("gates.max_length"), std::string::npos);
  }
  // Steps and bins so fine that the search ran for hours or ran out of memory.
  ObjectSegmentationConfig fine;
  fine.walls.angle_step_deg = 1e-9;
  EXPECT_THROW(validate(fine), std::invalid_argument);
  fine = ObjectSegmentationConfig();
  fine.walls.thickness = 1e-9;
  EXPECT_THROW(validate(fine), std::invalid_argument);
  fine = ObjectSegmentationConfig();
  fine.gates.side_bin = 1e-9;
  EXPECT_THROW(validate(fine), std::invalid_argument);
}

TEST(ObjectSegmentationTest, TheStagesValidationNamesTheSection) {
  // Both methods have a cell_size: a message must say whose.
  const auto message = [](const std::function<void(SegmentationStageConfig&)>& change) {
    SegmentationStageConfig config;
    change(config);
    try {
      validate(config);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(message([](SegmentationStageConfig&) {}), "accepted");
  EXPECT_NE(message([](SegmentationStageConfig& c) { c.objects.cell_size = 0.0; })
                .find("objects.cell_size"),
            std::string::npos);
  EXPECT_NE(message([](SegmentationStageConfig& c) { c.occupancy.cell_size = 0.001; })
                .find("occupancy: extent / cell_size"),
            std::string::npos);
}

}  // namespace
}  // namespace granular
