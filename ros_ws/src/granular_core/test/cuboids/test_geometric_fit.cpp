// Geometric cuboid fitting: the L-shape rectangle, size priors grown from the seen corner, the
// ground's tilt. (Over 400 lines: one case per way a vehicle is seen, all on the road, priors
// and error measures at the top.)
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "support/segment_data.h"
#include "support/visible_faces.h"

namespace granular {
namespace {

using testing_support::moved;
using testing_support::seenFaces;
using testing_support::seenFacesAndRoof;
using testing_support::segmentOnRoad;
using testing_support::unhiddenBy;
using testing_support::StandingBox;

constexpr double kSensorHeight = 1.73;
constexpr double kDeg = M_PI / 180.0;

// A road 1.73 m below the sensor, tilted by `roll_deg` about x and `pitch_deg` about y.
GroundPlane road(double roll_deg = 0.0, double pitch_deg = 0.0) {
  GroundPlane plane;
  plane.normal = Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()) *
                 Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX()) *
                 Eigen::Vector3d::UnitZ();
  plane.offset = kSensorHeight;
  return plane;
}

// One class, Car, of the test box's size.
CuboidConfig carPrior() {
  CuboidConfig config;
  config.priors = {{"Car", {4.5, 1.8, 1.5}}};
  config.geometric.classes = {"Car"};
  // Exact returns: the paper's d0. The default's 0.1 m, for a real sensor's noise, leaves the
  // closeness flat within about a degree of an exact corner.
  config.lshape.closeness_d0 = 0.01;
  return config;
}

// The test car's, a box truck's and a bus's priors: the truck the taller, the bus the longer.
CuboidConfig carTruckAndBusPriors() {
  CuboidConfig config = carPrior();
  config.priors = {{"Car", {4.5, 1.8, 1.5}}, {"BoxTruck", {7.2, 2.4, 3.3}},
                   {"SchoolBus", {11.0, 2.5, 3.1}}};
  config.geometric.classes = {"Car", "BoxTruck", "SchoolBus"};
  return config;
}

// The sensor-frame view of points given in the road's frame.
ObjectView view(const std::vector<Eigen::Vector3d>& on_road, const GroundPlane& ground) {
  ObjectView object;
  object.points = moved(on_road, ground.levelling().inverse());
  object.ground = ground;
  return object;
}

Eigen::Vector3d sensorInRoadFrame(const GroundPlane& ground) {
  return ground.levelling() * Eigen::Vector3d::Zero();
}

// Degrees between the box's length axis and `yaw` (road frame), modulo 180.
double headingError(const OrientedBox& box, const GroundPlane& ground, double yaw) {
  const Eigen::Vector3d axis =
      ground.levelling().linear() * (box.orientation() * Eigen::Vector3d::UnitX());
  const double difference = std::remainder(std::atan2(axis.y(), axis.x()) - yaw, M_PI);
  return std::abs(difference) / kDeg;
}

// Metres between the box's centre and the centre of `truth` standing on the road.
double centreError(const OrientedBox& box, const GroundPlane& ground, const StandingBox& truth) {
  const Eigen::Vector3d expected = ground.levelling().inverse() *
                                   Eigen::Vector3d(truth.centre.x(), truth.centre.y(),
                                                   truth.size.z() / 2);
  return (box.centre() - expected).norm();
}

// The fit is the test car: its heading within 0.5 deg, its centre within 2 cm, the prior's
// footprint.
void expectTheCar(const std::optional<FittedCuboid>& fitted, const GroundPlane& ground,
                  const StandingBox& car) {
  ASSERT_TRUE(fitted);
  EXPECT_LT(headingError(fitted->box, ground, car.yaw), 0.5);
  EXPECT_LT(centreError(fitted->box, ground, car), 0.02);
  EXPECT_NEAR(fitted->box.size().x(), 4.5, 0.02);
  EXPECT_NEAR(fitted->box.size().y(), 1.8, 0.02);
}

TEST(GeometricFitTest, AnLShapeSeenFromEachOfItsCornersGivesTheBox) {
  const GroundPlane ground = road();
  const GeometricCuboidFitter fitter(carPrior());
  for (int corner = 0; corner < 4; ++corner) {
    StandingBox car;
    car.centre = {10.0, 2.0};
    car.yaw = (33.7 + 90.0 * corner) * kDeg;
    const std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.05);
    const std::optional<FittedCuboid> fitted = fitter.fit(view(seen, ground));
    ASSERT_TRUE(fitted) << "corner " << corner;
    EXPECT_LT(headingError(fitted->box, ground, car.yaw), 0.5) << "corner " << corner;
    EXPECT_LT(centreError(fitted->box, ground, car), 0.02) << "corner " << corner;
    EXPECT_NEAR(fitted->box.size().x(), 4.5, 0.02) << "corner " << corner;
    EXPECT_NEAR(fitted->box.size().y(), 1.8, 0.02) << "corner " << corner;
    EXPECT_NEAR(fitted->box.size().z(), 1.5, 1e-9) << "corner " << corner;
    EXPECT_EQ(fitted->label, kUnknownLabel);
    EXPECT_EQ(fitted->points, seen.size());
    EXPECT_TRUE(fitted->heading_seen) << "corner " << corner;
  }
}

TEST(GeometricFitTest, APartlySeenCornerGrowsToThePriorFromTheSeenCorner) {
  const GroundPlane ground = road();
  StandingBox car;
  car.centre = {8.0, 6.0};
  car.yaw = 0.0;
  // The rear face and the first 2.5 m of the right side: the rest is hidden.
  const std::vector<Eigen::Vector3d> seen =
      seenFaces(car, sensorInRoadFrame(ground), 0.05,
                [](double u, double, double) { return u <= -2.25 + 2.5 + 1e-9; });
  expectTheCar(GeometricCuboidFitter(carPrior()).fit(view(seen, ground)), ground, car);
}

TEST(GeometricFitTest, ARearFaceGrowsAwayFromTheSensorToThePriorLength) {
  const GroundPlane ground = road();
  StandingBox car;
  car.centre = {12.0, 0.0};
  car.yaw = 2.0 * kDeg;
  const std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.05);
  // The rear is at x = 9.75: the box reaches 4.5 m beyond it, not towards the sensor.
  expectTheCar(GeometricCuboidFitter(carPrior()).fit(view(seen, ground)), ground, car);
}

TEST(GeometricFitTest, ASideFaceGrowsAwayFromTheSensorToThePriorWidth) {
  const GroundPlane ground = road();
  StandingBox car;
  car.centre = {0.5, -10.0};
  car.yaw = M_PI;
  const std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.05);
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(carPrior()).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_LT(headingError(fitted->box, ground, car.yaw), 0.5);
  EXPECT_LT(centreError(fitted->box, ground, car), 0.02);
  EXPECT_NEAR(fitted->box.size().y(), 1.8, 1e-9);
}

// A scan of `object_on_road` (road frame) and of the road all around it out to 40 m, the road's
// returns every 0.2 m of range and 0.2 deg of azimuth, in the sensor frame.
Cloud scanWithRoad(const std::vector<Eigen::Vector3d>& object_on_road,
                   const GroundPlane& ground) {
  std::vector<Eigen::Vector3d> points = object_on_road;
  for (double azimuth = -180.0; azimuth < 180.0; azimuth += 0.2) {
    for (double range = 2.0; range <= 40.0; range += 0.2) {
      points.emplace_back(range * std::cos(azimuth * kDeg), range * std::sin(azimuth * kDeg), 0.0);
    }
  }
  Cloud cloud;
  for (const Eigen::Vector3d& p : moved(points, ground.levelling().inverse())) {
    cloud.push_back(PointXYZIT(float(p.x()), float(p.y()), float(p.z()), 0.0f, 0.0));
  }
  return cloud;
}

TEST(GeometricFitTest, AShortCarWhoseWholeSideWasSeenKeepsItsLength) {
  const GroundPlane ground = road();
  const CuboidConfig config = carPrior();  // a 4.5 m prior
  StandingBox car;
  car.centre = {3.0, 6.0};
  car.size = {3.3, 1.8, 1.5};
  const std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.05);
  ObjectView object = view(seen, ground);
  // Told nothing of the space around it, the box grows to the prior.
  const std::optional<FittedCuboid> grown = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(grown);
  EXPECT_NEAR(grown->box.size().x(), 4.5, 1e-9);
  // The road was seen beyond the side's far end: the car ends there, give or take the probe
  // step (the first probe, 0.25 m beyond, shares its azimuth bin with the car's corner).
  const FreeSpace free_space(scanWithRoad(seen, ground), ground, config.free_space);
  object.free_space = &free_space;
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(fitted);
  EXPECT_GE(fitted->box.size().x(), 3.3 - 0.02);
  EXPECT_LE(fitted->box.size().x(), 3.3 + config.free_space.step + 0.02);
  EXPECT_LT(headingError(fitted->box, ground, car.yaw), 0.5);
  EXPECT_LT(centreError(fitted->box, ground, car), config.free_space.step / 2 + 0.02);
}

TEST(GeometricFitTest, ASideHiddenBehindAnotherObjectStillGrowsToThePrior) {
  const GroundPlane ground = road();
  const CuboidConfig config = carPrior();
  StandingBox car;
  car.centre = {8.0, 6.0};
  // The rear face and the first 2.5 m of the right side ...
  const std::vector<Eigen::Vector3d> seen =
      seenFaces(car, sensorInRoadFrame(ground), 0.05,
                [](double u, double, double) { return u <= -2.25 + 2.5 + 1e-9; });
  ObjectView object = view(seen, ground);
  const FreeSpace open_road(scanWithRoad(seen, ground), ground, config.free_space);
  object.free_space = &open_road;
  // ... with the road seen beyond them (the rest of the car was not there) ...
  const std::optional<FittedCuboid> short_box = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(short_box);
  EXPECT_GE(short_box->box.size().x(), 2.5 - 0.02);
  EXPECT_LE(short_box->box.size().x(), 2.5 + config.free_space.step + 0.02);
  // ... or hidden by something nearer the sensor, 6 m away across the bearings of the rest.
  std::vector<Eigen::Vector3d> scene = seen;
  for (double azimuth = 10.0; azimuth <= 32.0; azimuth += 0.1) {
    for (double h = 0.6; h <= 1.9; h += 0.2) {
      scene.emplace_back(6.0 * std::cos(azimuth * kDeg), 6.0 * std::sin(azimuth * kDeg), h);
    }
  }
  const FreeSpace hidden(scanWithRoad(scene, ground), ground, config.free_space);
  object.free_space = &hidden;
  expectTheCar(GeometricCuboidFitter(config).fit(object), ground, car);
}

TEST(GeometricFitTest, AFewPointsOverAGapAboveTheRoofAreAnOverhang) {
  const GroundPlane ground = road();
  CuboidConfig config = carPrior();
  config.priors = {{"Car", {4.5, 1.8, 1.5}}, {"Van", {5.1, 1.9, 2.2}}};
  config.geometric.classes = {"Car", "Van"};
  StandingBox car;
  car.centre = {8.0, 4.0};
  std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.05);
  // A branch 0.6 m over the roof: six returns, 2.1 m above the road.
  for (int i = 0; i < 6; ++i) {
    seen.emplace_back(7.0 + 0.1 * i, 3.5, 2.1);
  }
  ASSERT_LE(6.0, config.points.overhang_share * double(seen.size()));
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_NEAR(fitted->box.size().z(), 1.5, 1e-9);
  EXPECT_NEAR(fitted->box.size().x(), 4.5, 0.02);
  EXPECT_EQ(fitted->points, seen.size() - 6);
  // Closer over the roof than the gap, they are the object's own.
  config.points.overhang_gap = 0.7;
  const std::optional<FittedCuboid> tall = GeometricCuboidFitter(config).fit(view(seen, ground));
  ASSERT_TRUE(tall);
  EXPECT_NEAR(tall->box.size().z(), 2.1, 1e-9);
}

TEST(GeometricFitTest, ATruckCutAtTheHeightCapTakesTheShortestTallEnoughPrior) {
  const GroundPlane ground = road();
  CuboidConfig config = carTruckAndBusPriors();
  StandingBox truck;
  truck.centre = {12.0, 3.0};
  truck.yaw = 5.0 * kDeg;
  truck.size = {7.2, 2.4, 3.3};
  // The rear and the first 1.6 m of the side, cut 3 m above the road as the segmentation does.
  const std::vector<Eigen::Vector3d> seen =
      seenFaces(truck, sensorInRoadFrame(ground), 0.05, [](double u, double, double h) {
        return u <= -3.6 + 1.6 + 1e-9 && h <= 3.0;
      });
  ObjectView object = view(seen, ground);
  // Without the cap (and without taking a top under its nearest prior's as cut), the 3 m top
  // is nearest the bus's height.
  config.geometric.cut_top_above = 9.0;
  const std::optional<FittedCuboid> uncapped = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(uncapped);
  EXPECT_NEAR(uncapped->box.size().x(), 11.0, 1e-9);
  object.height_cap = 3.0;
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(fitted);
  // The 2.4 m rear is the width, though longer than the 1.6 m of side seen.
  EXPECT_LT(headingError(fitted->box, ground, truck.yaw), 0.5);
  EXPECT_NEAR(fitted->box.size().x(), 7.2, 1e-9);
  EXPECT_NEAR(fitted->box.size().y(), 2.4, 0.02);
  const Eigen::Vector3d expected = ground.levelling().inverse() *
                                   Eigen::Vector3d(truck.centre.x(), truck.centre.y(), 1.5);
  EXPECT_LT((fitted->box.centre() - expected).head<2>().norm(), 0.02);
}

TEST(GeometricFitTest, AFarTruckWhoseTopRingIsBelowTheCapStillReachesIt) {
  const GroundPlane ground = road();
  CuboidConfig config = carTruckAndBusPriors();
  StandingBox truck;
  truck.centre = {36.6, 0.0};
  truck.size = {7.2, 2.4, 3.3};
  // Its rear 33 m away; the highest ring on it 2.75 m up, the next one over the 3 m cap.
  const std::vector<Eigen::Vector3d> seen =
      seenFaces(truck, sensorInRoadFrame(ground), 0.05,
                [](double, double, double h) { return h <= 2.75; });
  ObjectView object = view(seen, ground);
  object.height_cap = 3.0;
  // 0.7 deg at 33 m is 0.40 m: the top is within reach of the cap, and the truck may be taller.
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(fitted);
  EXPECT_NEAR(fitted->box.size().x(), 7.2, 1e-9);
  EXPECT_LT(centreError(fitted->box, ground, StandingBox{truck.centre, 0.0, {7.2, 2.4, 2.75}}),
            0.05);
  // Judged by its height alone, 2.75 m is nearest the bus's 3.1 m.
  config.geometric.cap_reach_deg = 0.0;
  config.geometric.cut_top_above = 9.0;
  const std::optional<FittedCuboid> bus = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(bus);
  EXPECT_NEAR(bus->box.size().x(), 11.0, 1e-9);
}

TEST(GeometricFitTest, ATruckWhoseRoofTheHighestRingPassedUnderTakesTheShortestTallEnoughPrior) {
  // The HDL-64E's highest ring, 2 degrees up, passes 2.74 m above the road 29 m away: a box
  // truck's rear seen there up to 2.64 m, with no segmentation cap.
  const GroundPlane ground = road();
  CuboidConfig config = carTruckAndBusPriors();
  StandingBox truck;
  truck.centre = {32.6, 0.0};
  truck.size = {7.2, 2.4, 3.3};
  const std::vector<Eigen::Vector3d> seen =
      seenFaces(truck, sensorInRoadFrame(ground), 0.05,
                [](double, double, double h) { return h <= 2.64; });
  const ObjectView object = view(seen, ground);
  // Taller than a car, lower than its nearest prior (the bus's 3.1 m): it may be taller.
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(fitted);
  EXPECT_NEAR(fitted->box.size().x(), 7.2, 1e-9);
  EXPECT_LT(centreError(fitted->box, ground, StandingBox{truck.centre, 0.0, {7.2, 2.4, 2.64}}),
            0.05);
  // By its height alone it is the bus.
  config.geometric.cut_top_above = 9.0;
  const std::optional<FittedCuboid> bus = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(bus);
  EXPECT_NEAR(bus->box.size().x(), 11.0, 1e-9);
  // A bus seen up to its roof is no taller than its prior: it stays the bus.
  StandingBox school_bus = truck;
  school_bus.size = {11.0, 2.5, 3.1};
  config.geometric.cut_top_above = 2.2;
  const std::optional<FittedCuboid> whole = GeometricCuboidFitter(config).fit(
      view(seenFaces(school_bus, sensorInRoadFrame(ground), 0.05,
                     [](double, double, double) { return true; }),
           ground));
  ASSERT_TRUE(whole);
  EXPECT_NEAR(whole->box.size().x(), 11.0, 1e-9);
}

TEST(GeometricFitTest, ABusCutAtTheCapWhoseSideGoesOnPastATrucksLengthTakesTheBusPrior) {
  // Seen from behind at a slant, cut 3 m above the road: its segment holds the rear and the
  // first 2 m of the side (the rest of the side, sparse at a grazing angle, fell apart).
  const GroundPlane ground = road();
  CuboidConfig config = carTruckAndBusPriors();
  const auto fitted_length = [&](const StandingBox& vehicle) {
    const auto cut = [](double, double, double h) { return h <= 3.0; };
    const std::vector<Eigen::Vector3d> whole =
        seenFaces(vehicle, sensorInRoadFrame(ground), 0.05, cut);
    const double rear = -vehicle.size.x() / 2;
    ObjectView object = view(seenFaces(vehicle, sensorInRoadFrame(ground), 0.05,
                                       [&](double u, double v, double h) {
                                         return u <= rear + 2.0 + 1e-9 && cut(u, v, h);
                                       }),
                             ground);
    object.height_cap = 3.0;
    const FreeSpace free_space(scanWithRoad(whole, ground), ground, config.free_space);
    object.free_space = &free_space;
    const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(object);
    if (!fitted) {
      ADD_FAILURE() << "no cuboid";
      return 0.0;
    }
    // Grown from the seen rear (along x, yaw 0) to its length.
    const double length = fitted->box.size().x();
    EXPECT_LT(headingError(fitted->box, ground, vehicle.yaw), 0.5);
    EXPECT_LT(centreError(fitted->box, ground,
                          StandingBox{{vehicle.centre.x() + (length - vehicle.size.x()) / 2,
                                       vehicle.centre.y()},
                                      vehicle.yaw,
                                      {length, vehicle.size.y(), 3.0}}),
              0.05);
    return length;
  };
  StandingBox bus;
  bus.centre = {20.0, 3.0};
  bus.size = {11.0, 2.5, 3.1};
  StandingBox truck = bus;
  truck.size = {7.2, 2.4, 3.3};
  EXPECT_NEAR(fitted_length(bus), 11.0, 1e-9);
  // The truck's side ends where its prior does: it stays the truck.
  EXPECT_NEAR(fitted_length(truck), 7.2, 1e-9);
  // Without the rule the bus is the shortest prior tall enough, the truck.
  config.geometric.longer_occupied_steps = 0;
  EXPECT_NEAR(fitted_length(bus), 7.2, 1e-9);
}

TEST(GeometricFitTest, WheelsSeenBelowARearFaceDoNotMakeItASide) {
  const GroundPlane ground = road();
  CuboidConfig config = carPrior();
  config.priors = {{"BoxTruck", {7.2, 2.4, 3.3}}};
  config.geometric.classes = {"BoxTruck"};
  StandingBox truck;
  truck.centre = {14.6, 0.0};
  truck.size = {7.2, 2.4, 3.3};
  // Straight ahead: only the rear face, and below the box its wheels, 2 m deep.
  std::vector<Eigen::Vector3d> seen = seenFaces(truck, sensorInRoadFrame(ground), 0.05);
  for (double depth = 0.0; depth <= 2.0; depth += 0.1) {
    for (const double side : {-1.0, 1.0}) {
      seen.emplace_back(truck.centre.x() - 3.6 + depth, side, 0.45);
    }
  }
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_LT(headingError(fitted->box, ground, truck.yaw), 0.5);
  EXPECT_NEAR(fitted->box.size().x(), 7.2, 1e-9);
  EXPECT_LT(centreError(fitted->box, ground, truck), 0.05);
}

TEST(GeometricFitTest, ACarSeenEndOnAmongParkedCarsIsLongWhereNoNeighbourStands) {
  // Three cars parked in a row across the line of sight from the aisle, 0.8 m apart, their
  // lengths along y. Of the middle one the sensor sees its front, its roof and bonnet 1.8 m
  // deep and the start of its side: the nearer neighbour hides the rest. The farther
  // neighbour's front stands where the box would grow if its length ran along the line of sight.
  const GroundPlane ground = road();
  const CuboidConfig config = carPrior();
  const Eigen::Vector3d sensor = sensorInRoadFrame(ground);
  StandingBox car, nearer, farther;
  car.yaw = nearer.yaw = farther.yaw = M_PI / 2;
  car.centre = {-7.0, -6.2};
  nearer.centre = {-4.4, -6.2};
  farther.centre = {-9.6, -6.2};
  const auto all = [](double, double, double) { return true; };
  const auto front = [](double u, double, double) { return u >= 2.25 - 1.8 - 1e-9; };
  const std::vector<Eigen::Vector3d> nearer_seen = seenFacesAndRoof(nearer, sensor, 0.05, all);
  const std::vector<Eigen::Vector3d> seen =
      unhiddenBy(seenFacesAndRoof(car, sensor, 0.05, front), nearer_seen);
  std::vector<Eigen::Vector3d> scene = seen;
  scene.insert(scene.end(), nearer_seen.begin(), nearer_seen.end());
  for (const Eigen::Vector3d& p :
       unhiddenBy(unhiddenBy(seenFacesAndRoof(farther, sensor, 0.05, all), seen), nearer_seen)) {
    scene.push_back(p);
  }
  ObjectView object = view(seen, ground);
  // The sides seen alone take it for a car seen end on, long along the line of sight ...
  const std::optional<FittedCuboid> alone = GeometricCuboidFitter(config).fit(object);
  ASSERT_TRUE(alone);
  EXPECT_GT(headingError(alone->box, ground, car.yaw), 80.0);
  // ... where the scan saw the farther neighbour and the gap before it.
  const FreeSpace around(scanWithRoad(scene, ground), ground, config.free_space);
  object.free_space = &around;
  expectTheCar(GeometricCuboidFitter(config).fit(object), ground, car);
  CuboidConfig sides_only = config;
  sides_only.free_space.refuted_margin = 0;
  const std::optional<FittedCuboid> unchecked = GeometricCuboidFitter(sides_only).fit(object);
  ASSERT_TRUE(unchecked);
  EXPECT_GT(headingError(unchecked->box, ground, car.yaw), 80.0);
}

// The test car 14 m ahead on a flat road, seen from behind: its rear face, and the rear window
// and roof seen 1.7 m deep above it, as deep as the car is wide: either way may be its length.
struct EndOnWithRoof {
  GroundPlane ground = road();
  StandingBox car;
  std::vector<Eigen::Vector3d> seen;
};

EndOnWithRoof carSeenEndOnWithItsRoof() {
  EndOnWithRoof scene;
  scene.car.centre = {14.0, 0.3};
  scene.car.yaw = 1.0 * kDeg;
  scene.seen = seenFaces(scene.car, sensorInRoadFrame(scene.ground), 0.05);
  const Eigen::Rotation2Dd turn(scene.car.yaw);
  for (double depth = 0.0; depth <= 1.7; depth += 0.05) {
    for (double across = -0.85; across <= 0.85; across += 0.05) {
      const Eigen::Vector2d p = scene.car.centre + turn * Eigen::Vector2d(-2.25 + depth, across);
      scene.seen.emplace_back(p.x(), p.y(), 1.5);
    }
  }
  return scene;
}

TEST(GeometricFitTest, ACarSeenEndOnWithItsRoofIsLongAlongTheLineOfSight) {
  const EndOnWithRoof scene = carSeenEndOnWithItsRoof();
  expectTheCar(GeometricCuboidFitter(carPrior()).fit(view(scene.seen, scene.ground)),
               scene.ground, scene.car);
}

TEST(GeometricFitTest, AHeadingLentByTheNeighboursTurnsACarWhosePointsLeftItOpen) {
  const EndOnWithRoof scene = carSeenEndOnWithItsRoof();
  const GroundPlane& ground = scene.ground;
  const StandingBox& car = scene.car;
  const GeometricCuboidFitter fitter(carPrior());
  ObjectView object = view(scene.seen, ground);
  const std::optional<FittedCuboid> own = fitter.fit(object);
  ASSERT_TRUE(own);
  EXPECT_FALSE(own->heading_seen);
  EXPECT_LT(headingError(own->box, ground, car.yaw), 0.5);

  object.heading = car.yaw + M_PI / 2;
  const std::optional<FittedCuboid> lent = fitter.fit(object);
  ASSERT_TRUE(lent);
  EXPECT_FALSE(lent->heading_seen);
  EXPECT_LT(headingError(lent->box, ground, car.yaw + M_PI / 2), 0.5);
  EXPECT_NEAR(lent->box.size().x(), 4.5, 0.02);
  EXPECT_NEAR(lent->box.size().y(), 1.8, 0.02);
}

TEST(GeometricFitTest, AJeepsRearWithASpareWheelIsNotTurnedByTheWheel) {
  // Seven columns of a Jeep's rear 15.6 m ahead, two of them on the spare wheel 0.2 m nearer:
  // the closeness criterion with d0 0.1 m lines the rectangle up along the wheel and a corner,
  // 22 degrees off; fitted again with d0 0.2 m, the rear's own columns decide.
  const std::vector<Eigen::Vector3d> seen = segmentOnRoad("road_jeep_rear_spare_wheel.xyz");
  ASSERT_EQ(seen.size(), 53u);
  const GroundPlane ground = road();
  CuboidConfig config;
  config.priors = {{"SUV", {4.80, 1.94, 1.80}}, {"Jeep", {4.42, 1.96, 1.85}}};
  config.geometric.classes = {"SUV", "Jeep"};
  const double jeep_yaw = -0.7 * kDeg;
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_LT(headingError(fitted->box, ground, jeep_yaw), 2.0);

  CuboidConfig one_criterion = config;
  one_criterion.lshape.face_closeness_d0 = 0.0;
  const std::optional<FittedCuboid> turned =
      GeometricCuboidFitter(one_criterion).fit(view(seen, ground));
  ASSERT_TRUE(turned);
  EXPECT_GT(headingError(turned->box, ground, jeep_yaw), 15.0);
}

TEST(GeometricFitTest, AFarTruckSeenEndOnBetweenSparseColumnsIsLongAlongTheLineOfSight) {
  const GroundPlane ground = road();
  CuboidConfig config = carPrior();
  config.priors = {{"BoxTruck", {7.2, 2.4, 3.3}}};
  config.geometric.classes = {"BoxTruck"};
  StandingBox truck;
  truck.centre = {49.0, 0.0};
  truck.size = {7.2, 2.4, 3.3};
  // A 1 degree scan 45 m away (the simulator's): three columns of returns 0.79 m apart on the
  // 2.4 m rear face, so that it looks 1.6 m wide, and above the cab the box's face 2 m
  // deeper, so that the truck looks as deep as a truck is wide. Taken across the line of sight
  // instead, its 7.2 m stood sideways, 3.7 m from the truck's centre.
  std::vector<Eigen::Vector3d> seen;
  for (const double bearing : {-1.0, 0.0, 1.0}) {
    for (const auto& [depth, heights] :
         {std::make_pair(0.0, std::vector<double>{0.5, 1.0, 1.5, 2.0}),
          std::make_pair(2.0, std::vector<double>{2.6, 3.2})}) {
      const double x = 45.4 + depth;
      for (const double height : heights) {
        seen.emplace_back(x, x * std::tan(bearing * kDeg), height);
      }
    }
  }
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_LT(headingError(fitted->box, ground, truck.yaw), 1.0);
  EXPECT_NEAR(fitted->box.size().x(), 7.2, 1e-9);
  // Its width grows from columns around the line of sight, either way.
  EXPECT_LT(centreError(fitted->box, ground, truck), 0.5);
}

TEST(GeometricFitTest, ADimensionLongerThanThePriorStays) {
  const GroundPlane ground = road();
  StandingBox van;
  van.centre = {9.0, 7.0};
  van.yaw = 20.0 * kDeg;
  van.size = {6.0, 2.1, 2.0};
  const std::vector<Eigen::Vector3d> seen = seenFaces(van, sensorInRoadFrame(ground), 0.05);
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(carPrior()).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_NEAR(fitted->box.size().x(), 6.0, 0.02);
  EXPECT_NEAR(fitted->box.size().y(), 2.1, 0.02);
  EXPECT_LT(centreError(fitted->box, ground, van), 0.02);
}

TEST(GeometricFitTest, TheHeightIsThePriorsWhenFewPointsSaySo) {
  const GroundPlane ground = road();
  CuboidConfig config = carPrior();
  config.geometric.height_points = 1000;
  StandingBox car;
  car.centre = {12.0, 0.0};
  car.size = {4.5, 1.8, 1.2};
  const std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.1);
  ASSERT_LT(seen.size(), 1000u);
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(config).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_NEAR(fitted->box.size().z(), 1.5, 1e-9);
}

TEST(GeometricFitTest, ATiltedRoadGivesTheBoxItsRollAndPitch) {
  const GroundPlane ground = road(3.0, -2.0);
  StandingBox car;
  car.centre = {9.0, -4.0};
  car.yaw = 61.3 * kDeg;
  const std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.05);
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(carPrior()).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  const Eigen::Vector3d up = fitted->box.orientation() * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(up.dot(ground.normal), 1.0, 1e-12);
  EXPECT_GT(std::acos(up.z()) / kDeg, 3.0);  // the box leans with the road
  EXPECT_LT(headingError(fitted->box, ground, car.yaw), 0.5);
  EXPECT_LT(centreError(fitted->box, ground, car), 0.02);
}

TEST(GeometricFitTest, SmallObjectsKeepTheSeenRectangle) {
  const GroundPlane ground = road();
  StandingBox person;
  person.centre = {6.0, 1.0};
  person.size = {0.5, 0.6, 1.7};
  const std::vector<Eigen::Vector3d> seen = seenFaces(person, sensorInRoadFrame(ground), 0.05);
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(carPrior()).fit(view(seen, ground));
  ASSERT_TRUE(fitted);
  EXPECT_LE(fitted->box.size().x(), 0.6 + 1e-9);
  EXPECT_LE(fitted->box.size().y(), 0.6 + 1e-9);
}

// A cyclist seen from the side, 14 m to the left, riding along x: the bicycle 1.8 m long up to
// its saddle and handlebar (1.0 m), the rider's back and head above it, 0.5 m long.
std::vector<Eigen::Vector3d> cyclistFromTheSide() {
  std::vector<Eigen::Vector3d> points;
  for (double u = -0.9; u <= 0.9 + 1e-9; u += 0.05) {
    for (double z = 0.3; z <= 1.0 + 1e-9; z += 0.1) {
      points.emplace_back(10.0 + u, 14.0 - 0.3, z);
    }
  }
  for (double u = -0.3; u <= 0.2 + 1e-9; u += 0.05) {
    for (double z = 1.1; z <= 1.75 + 1e-9; z += 0.1) {
      points.emplace_back(10.0 + u, 14.0 - 0.2, z);
    }
  }
  return points;
}

TEST(GeometricFitTest, ACyclistKeepsTheSeenRectangleInsteadOfACarsPrior) {
  const GroundPlane ground = road();
  const std::optional<FittedCuboid> fitted =
      GeometricCuboidFitter(carPrior()).fit(view(cyclistFromTheSide(), ground));
  ASSERT_TRUE(fitted);
  EXPECT_NEAR(fitted->box.size().x(), 1.8, 0.02);
  EXPECT_LT(fitted->box.size().y(), 0.2);
  EXPECT_NEAR(fitted->box.centre().x(), 10.0, 0.02);

  // Without the rule the bicycle's 1.8 m are a car's side, grown to the car's length.
  CuboidConfig no_riders = carPrior();
  no_riders.geometric.rider_width = 0.0;
  const std::optional<FittedCuboid> car =
      GeometricCuboidFitter(no_riders).fit(view(cyclistFromTheSide(), ground));
  ASSERT_TRUE(car);
  EXPECT_NEAR(car->box.size().x(), 4.5, 0.02);
}

TEST(GeometricFitTest, RoadReturnsAndTooFewPointsGiveNoCuboid) {
  const GroundPlane ground = road();
  const GeometricCuboidFitter fitter(carPrior());
  // Road returns only: below points.min_height.
  EXPECT_FALSE(fitter.fit(view({{5.0, 1.0, 0.1}, {5.2, 1.0, 0.05}, {5.4, 1.1, 0.2}, {5, 0, 0}},
                               ground)));
  EXPECT_FALSE(fitter.fit(view({{5.0, 1.0, 1.0}, {5.2, 1.0, 1.0}}, ground)));
  EXPECT_FALSE(fitter.fit(ObjectView()));
}

TEST(GeometricFitTest, WithoutAGroundTheBoxStandsOnTheLowestPoint) {
  const GroundPlane ground = road();
  StandingBox car;
  car.centre = {8.0, 6.0};
  std::vector<Eigen::Vector3d> seen = seenFaces(car, sensorInRoadFrame(ground), 0.05);
  ObjectView object = view(seen, ground);
  object.ground.reset();
  const std::optional<FittedCuboid> fitted = GeometricCuboidFitter(carPrior()).fit(object);
  ASSERT_TRUE(fitted);
  // The lowest points are 0.35 m above the road, at z = 0.35 - 1.73 in the sensor frame.
  const double bottom = fitted->box.centre().z() - fitted->box.size().z() / 2;
  EXPECT_NEAR(bottom, 0.35 - kSensorHeight, 1e-9);
  EXPECT_NEAR(fitted->box.size().z(), 1.5 - 0.35, 1e-9);
  EXPECT_LT((fitted->box.centre().head<2>() - car.centre).norm(), 0.02);
}

}  // namespace
}  // namespace granular
