// VehicleEvidence: a canopy that rays pass through is no vehicle, an opaque box of the same
// size is one, on a scan cast ray by ray.
#include <cmath>

#include <gtest/gtest.h>

#include "granular_core/cuboids/vehicle_evidence.h"
#include "support/ray_cast.h"

namespace granular {
namespace {

constexpr double kSensorHeight = 1.73;
constexpr double kAzimuthStepDeg = 0.2;

using testing_support::Block;

// The scan of `blocks` by a 64-ring sensor kSensorHeight above the road, kAzimuthStepDeg
// between returns, 60 degrees either side of +x.
Cloud scan(const std::vector<Block>& blocks) {
  return testing_support::rayCastScan(blocks, {kSensorHeight, kAzimuthStepDeg, 60.0});
}

GroundPlane flatRoad() {
  GroundPlane plane;
  plane.offset = kSensorHeight;
  return plane;
}

// A car-sized block 10 m ahead and a little to the left, seen at its corner.
Block carSized(double density) {
  return {{9.0, 1.0, -kSensorHeight}, {13.5, 2.8, -kSensorHeight + 1.5}, density};
}

// A car: its body up to 1 m, and a cabin over its middle up to 1.5 m (the roof higher than
// bonnet and boot), as carSized(0) bounds it.
std::vector<Block> car() {
  return {{{9.0, 1.0, -kSensorHeight}, {13.5, 2.8, -kSensorHeight + 1.0}, 0.0},
          {{10.2, 1.15, -kSensorHeight + 1.0}, {12.4, 2.65, -kSensorHeight + 1.5}, 0.0}};
}

// The returns inside `bounds` (above the road) and the cuboid it is, for a sensor with
// `azimuth_step_deg` between returns.
VehicleCues measured(const Cloud& cloud, const Block& bounds, VehicleVerdict& verdict,
                     const VehicleEvidenceConfig& config = VehicleEvidenceConfig(),
                     double azimuth_step_deg = kAzimuthStepDeg) {
  std::vector<Eigen::Vector3d> points;
  for (const PointXYZIT& p : cloud) {
    const Eigen::Vector3d point(p.x, p.y, p.z);
    if ((point.array() >= bounds.low.array() - 1e-6).all() &&
        (point.array() <= bounds.high.array() + 1e-6).all() &&
        point.z() > -kSensorHeight + 0.05) {
      points.push_back(point);
    }
  }
  const OrientedBox cuboid((bounds.low + bounds.high) / 2.0, Eigen::Quaterniond::Identity(),
                           bounds.high - bounds.low);
  const VehicleEvidence evidence(cloud, flatRoad(), config, azimuth_step_deg);
  const VehicleCues cues = evidence.measure(points, cuboid);
  verdict = evidence.judge(cues);
  return cues;
}

TEST(VehicleEvidenceTest, AnOpaqueCarIsAVehicle) {
  VehicleVerdict verdict;
  const VehicleCues cues = measured(scan(car()), carSized(0.0), verdict);
  EXPECT_EQ(cues.pass_share, 0.0);  // nothing returns from behind an opaque body
  EXPECT_GE(cues.fill, 0.95);
  EXPECT_LT(cues.face_distance, 0.01);  // every body return on the faces turned to the sensor
  EXPECT_NEAR(cues.top, 1.5, 0.05);
  EXPECT_GT(cues.profile_drop, 0.4);  // bonnet and boot lower than the roof
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, ACuboidNarrowerThanACarIsTooThin) {
  // A clipped hedge 4.5 m long, 1.2 m deep and car-high, dense enough to return every ray: a
  // body by every other cue. Its cuboid is as narrow as the fit found it, having seen the road
  // behind it.
  const Block hedge{{9.0, 1.0, -kSensorHeight}, {13.5, 2.2, -kSensorHeight + 1.5}, 0.0};
  VehicleVerdict verdict;
  EXPECT_NEAR(measured(scan({hedge}), hedge, verdict).cuboid_width, 1.2, 1e-9);
  EXPECT_EQ(verdict, VehicleVerdict::kTooThin) << verdictName(verdict);
  VehicleEvidenceConfig any_width;
  any_width.min_width = 0.0;
  measured(scan({hedge}), hedge, verdict, any_width);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, ACanopyOfTheSameSizeThatRaysPassThroughIsBackground) {
  // Foliage: on average a return every 1.5 m inside, so rays often cross its 1.8-4.5 m.
  const Block canopy = carSized(1.0 / 1.5);
  VehicleVerdict verdict;
  const VehicleCues cues = measured(scan({canopy}), canopy, verdict);
  EXPECT_GT(cues.pass_share, 0.15);
  EXPECT_EQ(verdict, VehicleVerdict::kSeeThrough) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, AWallOrAHedgeLineIsNoCar) {
  // As high as a car, but level along its 7 m (and 0.3 m thin: too_thin besides, not asked
  // here), seen nearly end on: it spans about 1 m across the line of sight, too_small first.
  const Block wall{{9.0, 1.0, -kSensorHeight}, {16.0, 1.3, -kSensorHeight + 1.5}, 0.0};
  VehicleVerdict verdict;
  EXPECT_LT(measured(scan({wall}), wall, verdict).across_sight, 1.2);
  EXPECT_EQ(verdict, VehicleVerdict::kTooSmall) << verdictName(verdict);
  VehicleEvidenceConfig any_span;
  any_span.min_across_sight = 0.0;
  measured(scan({wall}), wall, verdict, any_span);
  EXPECT_EQ(verdict, VehicleVerdict::kTooThin) << verdictName(verdict);
  VehicleEvidenceConfig any_width = any_span;
  any_width.min_width = 0.0;
  measured(scan({wall}), wall, verdict, any_width);
  EXPECT_EQ(verdict, VehicleVerdict::kTooLong) << verdictName(verdict);
  // A car's length, but a level top: refused where the bonnet and boot must show (the default
  // asks only that the ends are no higher than the middle), while the car passes.
  VehicleEvidenceConfig level_tops;
  level_tops.min_profile_drop = 0.2;
  measured(scan({carSized(0.0)}), carSized(0.0), verdict, level_tops);
  EXPECT_EQ(verdict, VehicleVerdict::kFlatTop) << verdictName(verdict);
  measured(scan(car()), carSized(0.0), verdict, level_tops);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, AWallFaceSeenBroadsideIsNoCarACarSeenSoIs) {
  // 12 m ahead, across the line of sight, 4.5 m long: a wall 1.9 m high (above the sensor, so
  // its top is not seen) with a pier in its middle to 2 m, so that its ends are no higher than
  // its middle (flat_top's default), and a car (body to 1 m, cabin 0.15 m in from its flank to
  // 1.5 m). Both within the car's cuboid, 1.8 m deep, as the fit grows it into the unseen space.
  const double road = -kSensorHeight;
  const std::vector<Block> wall = {{{12.0, -2.25, road}, {12.3, 2.25, road + 1.9}, 0.0},
                                   {{12.0, -0.25, road}, {12.3, 0.25, road + 2.0}, 0.0}};
  const Block wall_cuboid{{12.0, -2.25, road}, {13.8, 2.25, road + 2.0}, 0.0};
  VehicleVerdict verdict;
  VehicleCues cues = measured(scan(wall), wall_cuboid, verdict);
  EXPECT_NEAR(cues.seen_length, 4.5, 0.1);
  EXPECT_LT(cues.seen_width, 0.01);  // one plane
  EXPECT_EQ(verdict, VehicleVerdict::kOnePlane) << verdictName(verdict);
  VehicleEvidenceConfig any_plane;
  any_plane.min_seen_width = 0.0;
  measured(scan(wall), wall_cuboid, verdict, any_plane);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);

  const std::vector<Block> car = {{{12.0, -2.25, road}, {13.8, 2.25, road + 1.0}, 0.0},
                                  {{12.15, -1.1, road + 1.0}, {13.65, 1.1, road + 1.5}, 0.0}};
  const Block car_cuboid{{12.0, -2.25, road}, {13.8, 2.25, road + 1.5}, 0.0};
  cues = measured(scan(car), car_cuboid, verdict);
  EXPECT_GT(cues.seen_width, 1.0);  // its bonnet, roof and boot seen from above
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, TallObjectsStandingOnTheRoadAreNoVehicles) {
  // 25 m away, where the highest ring (2 degrees up) passes 2.6 m above the road. A wall piece
  // as tall as a bus reaches the road: no body clearance underneath.
  const Block wall{{25.0, 1.0, -kSensorHeight}, {29.5, 3.5, -kSensorHeight + 3.0}, 0.0};
  VehicleVerdict verdict;
  VehicleCues cues = measured(scan({wall}), wall, verdict);
  EXPECT_GT(cues.top, 2.2);
  EXPECT_EQ(verdict, VehicleVerdict::kTallOnTheRoad) << verdictName(verdict);
  // The same with its body 0.6 m clear of the road, as a bus's between the wheels.
  const Block bus{{25.0, 1.0, -kSensorHeight + 0.6}, {29.5, 3.5, -kSensorHeight + 3.0}, 0.0};
  cues = measured(scan({bus}), bus, verdict);
  EXPECT_GT(cues.clear_share, 0.5);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, ABoxTruckSeenEndOnIsAVehicleATreeAsTallIsNot) {
  // A box truck 40 m straight ahead, seen from behind: its rear face 2.4 m wide up to 3.2 m,
  // with its bumper and wheels reaching the road across it (no clearance seen under it). 40 m
  // away the highest ring (2 degrees up) passes 3.1 m above the road, so the roof's edge shows.
  const double road = -kSensorHeight;
  const std::vector<Block> truck = {{{40.0, -1.2, road}, {40.3, 1.2, road + 1.0}, 0.0},
                                    {{40.0, -1.2, road + 1.0}, {47.2, 1.2, road + 3.2}, 0.0}};
  const Block truck_cuboid{{40.0, -1.2, road}, {47.2, 1.2, road + 3.2}, 0.0};
  VehicleVerdict verdict;
  VehicleCues cues = measured(scan(truck), truck_cuboid, verdict);
  EXPECT_GE(cues.top, 2.6);
  EXPECT_LT(cues.clear_share, 0.5);  // the clearance test alone would refuse it
  // The rear face near the top, across the line of sight: 2.4 m less the step between
  // returns at each end (0.2 degrees at 40 m, 0.14 m).
  EXPECT_NEAR(cues.end_face_width, 2.4, 0.3);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
  VehicleEvidenceConfig no_end_on;
  no_end_on.end_on_max_length = 0.0;
  measured(scan(truck), truck_cuboid, verdict, no_end_on);
  EXPECT_EQ(verdict, VehicleVerdict::kTallOnTheRoad) << verdictName(verdict);
  // A conifer as tall and as wide at its foot, narrowing to 1 m at the top: no face as wide
  // as a vehicle near its top.
  const std::vector<Block> tree = {{{40.0, -1.2, road}, {42.4, 1.2, road + 1.6}, 0.0},
                                   {{40.4, -0.8, road + 1.6}, {42.0, 0.8, road + 2.6}, 0.0},
                                   {{40.7, -0.5, road + 2.6}, {41.7, 0.5, road + 3.2}, 0.0}};
  const Block tree_cuboid{{40.0, -1.2, road}, {47.2, 1.2, road + 3.2}, 0.0};
  cues = measured(scan(tree), tree_cuboid, verdict);
  EXPECT_GE(cues.top, 2.6);
  EXPECT_NEAR(cues.end_face_width, 1.0, 0.3);
  // Not waived: its returns spread over its steps, not on one face.
  EXPECT_EQ(verdict, VehicleVerdict::kNotASurface) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, ATruckSeenAtASlantWithItsCabBeforeItsBoxIsAVehicleAWallPieceIsNot) {
  // The cues of a box truck seen from the front at a slant, 14 m away on the simulated road:
  // 4.6 m of it seen, so not end on; its body clear of the road along most of its side; its
  // front near the top 1.9 m wide; its body returns a median 0.18 m from a flat face (its cab
  // stands before its box).
  VehicleCues truck;
  truck.points = 300;
  truck.body_points = 150;
  truck.top = 2.99;
  truck.seen_length = 4.6;
  truck.seen_width = 2.2;
  truck.across_sight = 3.0;
  truck.cuboid_width = 2.4;
  truck.fill = 1.0;
  truck.face_distance = 0.18;
  truck.clear_share = 0.6;
  truck.end_face_width = 1.9;
  VehicleEvidenceConfig config;
  config.box_face_max_distance = 0.25;
  const Cloud road_only = scan({});
  const auto verdict = [&](const VehicleCues& cues, const VehicleEvidenceConfig& with) {
    return VehicleEvidence(road_only, flatRoad(), with, kAzimuthStepDeg).judge(cues);
  };
  EXPECT_EQ(verdict(truck, config), VehicleVerdict::kVehicle);
  VehicleEvidenceConfig off = config;
  off.box_face_max_distance = 0.0;
  EXPECT_EQ(verdict(truck, off), VehicleVerdict::kTallOnTheRoad);
  // A wall piece as wide at its top, standing on the road: the clearance is still asked.
  VehicleCues wall = truck;
  wall.clear_share = 0.1;
  EXPECT_EQ(verdict(wall, config), VehicleVerdict::kTallOnTheRoad);
  // A tree crown, narrower at its top than a vehicle's face.
  VehicleCues crown = truck;
  crown.end_face_width = 1.0;
  EXPECT_EQ(verdict(crown, config), VehicleVerdict::kTallOnTheRoad);
  // Returns farther from a flat face than a cab before a box puts them.
  VehicleCues spread = truck;
  spread.face_distance = 0.3;
  EXPECT_EQ(verdict(spread, config), VehicleVerdict::kTallOnTheRoad);
}

TEST(VehicleEvidenceTest, ALongHedgeBehindAParkedCarIsNoTruck) {
  // KITTI 000000's hedge line: 7 m long and 2.4 m tall, 22 m away, a parked car before it
  // hiding its foot, so that its lowest returns stand high as a truck's body would.
  const Block hedge{{22.0, -3.5, -kSensorHeight}, {22.8, 3.5, -kSensorHeight + 2.4}, 0.0};
  const Block parked{{17.0, -2.2, -kSensorHeight}, {18.8, 2.3, -kSensorHeight + 1.5}, 0.0};
  const Cloud cloud = scan({hedge, parked});
  // Its block, 0.8 m deep, stands for the cuboid: too_thin besides, not asked here.
  VehicleEvidenceConfig any_width;
  any_width.min_width = 0.0;
  VehicleVerdict verdict;
  VehicleCues cues = measured(cloud, hedge, verdict, any_width);
  EXPECT_GT(cues.top, 2.2);             // taller than a car ...
  EXPECT_GE(cues.clear_share, 0.5);     // ... seemingly clear of the road ...
  EXPECT_GT(cues.seen_length, 6.5);     // ... and longer than one
  EXPECT_EQ(verdict, VehicleVerdict::kTooLong) << verdictName(verdict);
  // Long vehicles only as tall as a car's roof rack passed before min_long_top.
  VehicleEvidenceConfig car_tall = any_width;
  car_tall.min_long_top = car_tall.max_car_top;
  measured(cloud, hedge, verdict, car_tall);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
  // A box truck as long, 3.2 m tall with its body 0.6 m clear of the road, is one.
  const Block truck{{30.0, -3.5, -kSensorHeight + 0.6}, {32.4, 3.5, -kSensorHeight + 3.2}, 0.0};
  cues = measured(scan({truck}), truck, verdict);
  EXPECT_GE(cues.top, 2.6);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
}

// Columns of returns 20 m ahead, one per azimuth (deg) of a sensor with a 1 degree step, each
// at the heights (m above the road) of its pair.
Cloud columns(const std::vector<std::pair<double, std::vector<double>>>& returns) {
  Cloud cloud;
  for (const auto& [azimuth_deg, heights] : returns) {
    const double azimuth = azimuth_deg * M_PI / 180.0;
    for (const double height : heights) {
      cloud.push_back(PointXYZIT(20.0f, static_cast<float>(20.0 * std::tan(azimuth)),
                                 static_cast<float>(height - kSensorHeight), 0, 0.0));
    }
  }
  return cloud;
}

TEST(VehicleEvidenceTest, AnOutermostBinWithoutBodyReturnsIsNoGap) {
  // A sparse sensor's bins are wide (1 degree step: 2 degrees), so a car's outermost bin may
  // hold only what stands beside its body above the body band (a mirror, the cabin's edge):
  // that is no gap. Between returns in the band, a bin without one is (a fence's rails).
  constexpr double kStepDeg = 1.0;
  const std::vector<double> body{0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4};
  const std::vector<double> above_band{1.1, 1.2};
  // The rear of a car 1.75 m wide, in the bins of -4 to 2 degrees, and its mirror in the next.
  const Cloud car = columns({{-3.5, body}, {-2.5, body}, {-1.5, body}, {-0.5, body},
                             {0.5, body}, {1.5, body}, {2.5, above_band}, {3.5, above_band}});
  const Cloud fence = columns({{-3.5, body}, {-2.5, body}, {-1.5, above_band},
                               {-0.5, above_band}, {0.5, body}, {1.5, body}});
  const Block bounds{{20.0, -1.3, -kSensorHeight}, {24.5, 1.3, 1.5 - kSensorHeight}, 0.0};
  VehicleVerdict verdict;
  // Three bins with body returns of three; the mirror's not counted.
  EXPECT_EQ(measured(car, bounds, verdict, VehicleEvidenceConfig(), kStepDeg).fill, 1.0);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
  EXPECT_NEAR(measured(fence, bounds, verdict, VehicleEvidenceConfig(), kStepDeg).fill,
              2.0 / 3.0, 1e-12);
  EXPECT_EQ(verdict, VehicleVerdict::kGaps) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, AnObjectNarrowerAcrossTheLineOfSightThanACarIsNone) {
  // A dense bush 15 m ahead, 1.2 m across the line of sight and 2.5 m along it, as high as a
  // car: from any side a car spans at least its width (1.6 m and more) across the line of
  // sight. The cuboid's own width is left out (min_width 0) so that the span alone decides.
  VehicleEvidenceConfig config;
  config.min_width = 0.0;
  const Block bush{{15.0, -0.6, -kSensorHeight}, {17.5, 0.6, -kSensorHeight + 1.5}, 0.0};
  VehicleVerdict verdict;
  const VehicleCues bush_cues = measured(scan({bush}), bush, verdict, config);
  EXPECT_GT(bush_cues.across_sight, 1.2);
  EXPECT_LT(bush_cues.across_sight, config.min_across_sight);
  EXPECT_EQ(verdict, VehicleVerdict::kTooSmall) << verdictName(verdict);
  // A car seen end on at the same place, its rear 1.8 m wide, is one ...
  const Block rear{{15.0, -0.9, -kSensorHeight}, {19.5, 0.9, -kSensorHeight + 1.5}, 0.0};
  const VehicleCues car_cues = measured(scan({rear}), rear, verdict, config);
  EXPECT_GT(car_cues.across_sight, 1.8);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
  // A neighbour's front 1.2-1.8 m nearer, hiding its left edge as in a row of parked cars,
  // may hide the rest of it: its span then tells nothing, unless only what stands within 1 m
  // nearer may hide it.
  const Block beside{{13.2, 0.5, -kSensorHeight}, {13.6, 2.3, -kSensorHeight + 1.5}, 0.0};
  EXPECT_TRUE(measured(scan({bush, beside}), bush, verdict, config).side_hidden);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
  VehicleEvidenceConfig near_hides = config;
  near_hides.across_hide_depth = 1.0;
  EXPECT_FALSE(measured(scan({bush, beside}), bush, verdict, near_hides).side_hidden);
  EXPECT_EQ(verdict, VehicleVerdict::kTooSmall) << verdictName(verdict);
  EXPECT_FALSE(bush_cues.side_hidden);
  // ... and the bush alone passes with the rule off.
  config.min_across_sight = 0.0;
  measured(scan({bush}), bush, verdict, config);
  EXPECT_EQ(verdict, VehicleVerdict::kVehicle) << verdictName(verdict);
}

TEST(VehicleEvidenceTest, SmallAndLowThingsAreNoVehicles) {
  const Block post{{9.0, 1.0, -kSensorHeight}, {9.3, 1.3, -kSensorHeight + 1.5}, 0.0};
  VehicleVerdict verdict;
  measured(scan({post}), post, verdict);
  EXPECT_EQ(verdict, VehicleVerdict::kTooSmall) << verdictName(verdict);
  const Block kerb{{9.0, 1.0, -kSensorHeight}, {13.5, 2.8, -kSensorHeight + 0.6}, 0.0};
  measured(scan({kerb}), kerb, verdict);
  EXPECT_EQ(verdict, VehicleVerdict::kTooLow) << verdictName(verdict);
}

}  // namespace
}  // namespace granular
