// splitVehicles: touching parked cars are cut apart at the valleys of their height profile.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "granular_core/cuboids/free_space.h"
#include "granular_core/cuboids/vehicle_split.h"
#include "support/segment_data.h"

namespace granular {
namespace {

constexpr double kSensorHeight = 2.5;

// The upper faces and sides of a car (4.5 x 1.8 m, body to 1.0 m, roof to 1.5 m over its middle
// 2.2 m) centred at (x, y), its length at `yaw` (rad) from x, sampled every `step` m along it
// and 0.1 m across: what a mast sees.
void addCar(std::vector<Eigen::Vector3d>& points, double x, double y, double yaw = 0.0,
            double step = 0.1) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const auto add = [&](double u, double v, double h) {
    points.emplace_back(x + c * u - s * v, y + s * u + c * v, -kSensorHeight + h);
  };
  for (double u = -2.25; u <= 2.25 + 1e-9; u += step) {
    for (double v = -0.9; v <= 0.9 + 1e-9; v += 0.1) {
      const bool cabin = std::abs(u) <= 1.1 && std::abs(v) <= 0.75;
      add(u, v, cabin ? 1.5 : 1.0);
    }
    for (double h = 0.3; h < 1.0; h += 0.1) {
      add(u, -0.9, h);
      add(u, 0.9, h);
    }
  }
}

ObjectView viewOf(std::vector<Eigen::Vector3d> points) {
  ObjectView view;
  view.points = std::move(points);
  GroundPlane road;
  road.offset = kSensorHeight;
  view.ground = road;
  return view;
}

TEST(VehicleSplitTest, TwoCarsParkedHalfAMetreApartSideBySideAreTwoPieces) {
  std::vector<Eigen::Vector3d> points;
  addCar(points, 10.0, 0.0);
  const std::size_t first = points.size();
  addCar(points, 10.0, 2.3);  // 1.8 m wide each: 0.5 m between them
  const std::vector<ObjectView> pieces = splitVehicles(viewOf(points), VehicleSplitConfig());
  ASSERT_EQ(pieces.size(), 2u);
  // Each piece is one car: all of its points and none of the other's.
  std::vector<std::size_t> sizes{pieces[0].points.size(), pieces[1].points.size()};
  std::sort(sizes.begin(), sizes.end());
  EXPECT_EQ(sizes[0], first);
  EXPECT_EQ(sizes[1], points.size() - first);
  for (const ObjectView& piece : pieces) {
    double low = 1e9, high = -1e9;
    for (const Eigen::Vector3d& p : piece.points) {
      low = std::min(low, p.y()), high = std::max(high, p.y());
    }
    EXPECT_NEAR(high - low, 1.8, 1e-6);
    ASSERT_TRUE(piece.ground);
  }
}

TEST(VehicleSplitTest, NoseToTailCarsAreCutBetweenThem) {
  std::vector<Eigen::Vector3d> points;
  addCar(points, 10.0, 0.0);
  addCar(points, 15.1, 0.0);  // 0.6 m between the boot and the bonnet
  EXPECT_EQ(splitVehicles(viewOf(points), VehicleSplitConfig()).size(), 2u);
}

TEST(VehicleSplitTest, CarsSideBySideSeenFromTheirFrontsAreCutAlongTheRow) {
  // From the aisle a mast sees the front 2.4 m of two cars parked 0.5 m apart: a footprint 4.1 m
  // along the row, its longer side, and 2.4 m deep (the parking lot's turned cuboids).
  std::vector<Eigen::Vector3d> points;
  for (const double y : {0.0, 2.3}) {
    std::vector<Eigen::Vector3d> car;
    addCar(car, 10.0, y);
    for (const Eigen::Vector3d& p : car) {
      if (p.x() <= 10.0 - 2.25 + 2.4) {
        points.push_back(p);
      }
    }
  }
  const std::vector<ObjectView> pieces = splitVehicles(viewOf(points), VehicleSplitConfig());
  ASSERT_EQ(pieces.size(), 2u);
  for (const ObjectView& piece : pieces) {
    double low = 1e9, high = -1e9;
    for (const Eigen::Vector3d& p : piece.points) {
      low = std::min(low, p.y()), high = std::max(high, p.y());
    }
    EXPECT_NEAR(high - low, 1.8, 1e-6);  // one car's width each
  }
}

// The returns of a segment of the simulated parking lot in test/data (x, y, height above the
// road a line), in the sensor frame.
std::vector<Eigen::Vector3d> parkingLotSegment(const std::string& name) {
  std::vector<Eigen::Vector3d> points = testing_support::segmentOnRoad(name);
  for (Eigen::Vector3d& point : points) {
    point.z() -= kSensorHeight;
  }
  return points;
}

// How many of `pieces` lie wholly below x = `below` and how many wholly above x = `above`,
// by their returns higher than `min_height` above the road.
std::pair<int, int> piecesEitherSide(const std::vector<ObjectView>& pieces, double below,
                                     double above, double min_height = -1e9) {
  std::pair<int, int> sides{0, 0};
  for (const ObjectView& piece : pieces) {
    double low = 1e9, high = -1e9;
    for (const Eigen::Vector3d& p : piece.points) {
      if (p.z() > -kSensorHeight + min_height) {
        low = std::min(low, p.x()), high = std::max(high, p.x());
      }
    }
    sides.first += high < below;
    sides.second += low > above;
  }
  return sides;
}

TEST(VehicleSplitTest, TwoFrontsSeenAtASlantAreCutAcrossTheGapBetweenThem) {
  // A segment of the simulated parking lot: an SUV's and a sedan's fronts, their lengths along
  // y, 0.7 m apart between x = -7.25 and -6.52. Its sparse returns make a footprint whose
  // minimum-area rectangle is turned 25 degrees off both cars: across neither of its sides do
  // their profiles part, across the gap's own direction (and their L-shape's edges) they do.
  const std::vector<Eigen::Vector3d> points = parkingLotSegment("parking_lot_two_fronts.xyz");
  ASSERT_EQ(points.size(), 408u);
  VehicleSplitConfig rectangle_only;
  rectangle_only.search_step_deg = 0.0;
  rectangle_only.edges_min_width = 0.0;
  EXPECT_EQ(splitVehicles(viewOf(points), rectangle_only).size(), 1u);
  const std::vector<ObjectView> pieces = splitVehicles(viewOf(points), VehicleSplitConfig());
  ASSERT_EQ(pieces.size(), 2u);
  // Each piece's returns above the road lie on one side of the gap: the SUV's, the sedan's.
  EXPECT_EQ(piecesEitherSide(pieces, -7.0, -6.8, 0.2), std::make_pair(1, 1));
}

TEST(VehicleSplitTest, APairNoWiderThanTwoCarsIsCutOnlyAtEmptyGroundBetweenThem) {
  // A Jeep's front (x up to 8.01) and an SUV's side (from x = 8.5), 0.5 m apart at a slant:
  // their footprint's minimum-area rectangle is turned 47 degrees and 2.12 m wide, narrower
  // than search_min_width, and neither of its sides shows a valley. Across x the ground
  // between them was seen empty.
  const std::vector<Eigen::Vector3d> points = parkingLotSegment("parking_lot_slanted_pair.xyz");
  ASSERT_EQ(points.size(), 273u);
  const std::vector<ObjectView> pieces = splitVehicles(viewOf(points), VehicleSplitConfig());
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_EQ(piecesEitherSide(pieces, 8.1, 8.4, 0.2), std::make_pair(1, 1));  // Jeep, SUV
  // Across the minimum-area rectangle's own sides nothing parts them.
  VehicleSplitConfig rectangle_only;
  rectangle_only.search_step_deg = 0.0;
  rectangle_only.edges_min_width = 0.0;
  EXPECT_EQ(splitVehicles(viewOf(points), rectangle_only).size(), 1u);
}

TEST(VehicleSplitTest, FrontsSideBySideAlongTheLineOfSightAreCutAlongTheRow) {
  // A hatchback's and an SUV's fronts, bonnets and roofs, 0.4 m apart (x 4.9 to 5.4), their
  // lengths along the line of sight: a footprint 4.2 m along the row and 3.4 m deep. The rings
  // spread over the roofs leave empty bins along the line of sight, inside both cars.
  const std::vector<Eigen::Vector3d> points =
      parkingLotSegment("parking_lot_fronts_along_sight.xyz");
  ASSERT_EQ(points.size(), 139u);
  // One piece the hatchback's, one the SUV's.
  const auto oneCarEach = [](const std::vector<ObjectView>& pieces) {
    return piecesEitherSide(pieces, 5.0, 5.3) == std::make_pair(1, 1);
  };
  const std::vector<ObjectView> pieces = splitVehicles(viewOf(points), VehicleSplitConfig());
  EXPECT_EQ(pieces.size(), 2u);
  EXPECT_TRUE(oneCarEach(pieces));
  // Cut across the width first, the depth is cut between the rings on the roofs.
  VehicleSplitConfig width_first;
  width_first.sight_gap_deg = 0.0;
  EXPECT_FALSE(oneCarEach(splitVehicles(viewOf(points), width_first)));
}

TEST(VehicleSplitTest, TwoStaggeredFrontsAreCutAlongTheirOwnEdges) {
  // A Jeep's and an SUV's fronts and near sides, nothing between x = 7.4 and 7.9, the SUV's
  // front 0.75 m nearer the aisle: the minimum-area rectangle of their footprint lies across
  // both, 4.9 m by 1.9 m (no wider than one car); along the fronts' and sides' own edges the
  // footprint is 4.0 m by 3.2 m.
  const std::vector<Eigen::Vector3d> points =
      parkingLotSegment("parking_lot_staggered_pair.xyz");
  ASSERT_EQ(points.size(), 315u);
  const std::vector<ObjectView> pieces = splitVehicles(viewOf(points), VehicleSplitConfig());
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_EQ(piecesEitherSide(pieces, 7.5, 7.8), std::make_pair(1, 1));  // Jeep, SUV
  // Without looking along its edges, the footprint is one car's.
  VehicleSplitConfig minimum_area_only;
  minimum_area_only.edges_min_width = 0.0;
  EXPECT_EQ(splitVehicles(viewOf(points), minimum_area_only).size(), 1u);
}

TEST(VehicleSplitTest, TheSpacingBetweenASparseScansColumnsIsNoGap) {
  // A car 2.1 m wide with its mirrors, its returns in columns 0.25 m apart along it: a bin of
  // the profile empty between some two columns, and no car behind the other.
  std::vector<Eigen::Vector3d> car;
  addCar(car, 10.0, 0.0, 0.0, 0.25);
  car.emplace_back(10.0, 1.05, -kSensorHeight + 1.0);
  car.emplace_back(10.0, -1.05, -kSensorHeight + 1.0);
  EXPECT_EQ(splitVehicles(viewOf(car), VehicleSplitConfig()).size(), 1u);
  VehicleSplitConfig every_empty_bin;
  every_empty_bin.min_gap = 0.0;
  EXPECT_GT(splitVehicles(viewOf(car), every_empty_bin).size(), 1u);
}

TEST(VehicleSplitTest, TwoFrontsSeenAsOneFaceArePartedWhereRaysPassBetweenThem) {
  // From the aisle 8 m away a mast sees the fronts of two cars parked 0.5 m apart as one face,
  // 4.1 m along the row and 0.3 m deep (to their bonnets' edges): no wider than a car, shorter
  // than two nose to tail, as high at their corners as anywhere.
  std::vector<Eigen::Vector3d> points;
  const auto addFront = [&](double from, double to) {
    for (double y = from; y <= to + 1e-9; y += 0.1) {
      for (double h = 0.3; h <= 1.0 + 1e-9; h += 0.1) {
        points.emplace_back(8.0, y, -kSensorHeight + h);
      }
      points.emplace_back(8.3, y, -kSensorHeight + 1.0);
    }
  };
  addFront(-2.05, -0.25);
  const std::size_t first = points.size();
  addFront(0.25, 2.05);
  // The scan: the fronts, and through the gap between them a car's side 6 m further.
  Cloud cloud;
  for (const Eigen::Vector3d& p : points) {
    cloud.push_back(PointXYZIT(float(p.x()), float(p.y()), float(p.z()), 0.0f, 0.0));
  }
  Cloud fronts_only = cloud;
  for (double y = -0.3; y <= 0.3 + 1e-9; y += 0.05) {
    cloud.push_back(PointXYZIT(14.0f, float(y), float(-kSensorHeight + 0.8), 0.0f, 0.0));
  }
  GroundPlane road;
  road.offset = kSensorHeight;
  const FreeSpace scan(cloud, road, FreeSpaceConfig());
  ObjectView view = viewOf(points);
  view.free_space = &scan;
  const std::vector<ObjectView> pieces = splitVehicles(view, VehicleSplitConfig());
  ASSERT_EQ(pieces.size(), 2u);
  std::vector<std::size_t> sizes{pieces[0].points.size(), pieces[1].points.size()};
  std::sort(sizes.begin(), sizes.end());
  EXPECT_EQ(sizes[0], first);
  EXPECT_EQ(sizes[1], points.size() - first);
  // One face without the rule, where no ray was seen to pass between them, or with fewer
  // returns on a side than gap_min_points.
  VehicleSplitConfig off;
  off.gap_min_length = 0.0;
  EXPECT_EQ(splitVehicles(view, off).size(), 1u);
  const FreeSpace blind(fronts_only, road, FreeSpaceConfig());
  view.free_space = &blind;
  EXPECT_EQ(splitVehicles(view, VehicleSplitConfig()).size(), 1u);
  view.free_space = &scan;
  VehicleSplitConfig more_points;
  more_points.gap_min_points = first + 1;
  EXPECT_EQ(splitVehicles(view, more_points).size(), 1u);
}

TEST(VehicleSplitTest, OneCarOrATallerObjectIsLeftWhole) {
  std::vector<Eigen::Vector3d> car;
  addCar(car, 10.0, 0.0);
  EXPECT_EQ(splitVehicles(viewOf(car), VehicleSplitConfig()).size(), 1u);
  // Two cars under a 3 m tall awning: taller than a car, so a truck or a bus, not cut.
  std::vector<Eigen::Vector3d> points;
  addCar(points, 10.0, 0.0);
  addCar(points, 10.0, 2.3);
  points.emplace_back(10.0, 1.0, -kSensorHeight + 3.0);
  EXPECT_EQ(splitVehicles(viewOf(points), VehicleSplitConfig()).size(), 1u);
  VehicleSplitConfig off;
  off.enabled = false;
  points.pop_back();
  EXPECT_EQ(splitVehicles(viewOf(points), off).size(), 1u);
}

}  // namespace
}  // namespace granular
