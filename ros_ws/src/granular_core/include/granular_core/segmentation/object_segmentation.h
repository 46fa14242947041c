#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "granular_core/config/fields.h"
#include "granular_core/ground/ground.h"
#include "granular_core/point_types.h"
#include "granular_core/segmentation/background.h"
#include "granular_core/segmentation/occupancy_segmentation.h"

namespace granular {

/// Size and shape gates: what a segment must look like to be reported as an object. Each has a
/// physical reason (docs/segmentation.md gives the measurements); heights are above the
/// local ground.
struct SegmentGates {
  /// Fewer points above the ground cannot be classified: an object of N_thresh 10 points in
  /// its box holds a median of 8 above the ground stage's ground_height (the rest are road
  /// under and around it; docs/segmentation.md).
  std::size_t min_points = 7;
  double max_length = 14.0;      ///< m: no rigid road vehicle is longer
  /// m and m^2: vehicles are at most about 3 m wide and a bus is about 31 m^2, but parked cars
  /// touching side by side make one segment that the cuboid stage cuts apart (VehicleSplit).
  double max_width = 6.0;
  double max_area = 60.0;
  /// m: longer than wall_length and thinner than wall_width is a wall, fence or hedge line.
  double wall_length = 7.0;
  double wall_width = 0.6;
  /// ... unless it is a bus's or truck's side: its lowest point higher than side_clearance over
  /// at least side_share of its length (the body between the wheels; a wall, fence or hedge
  /// stands on the ground) and its top higher than side_top (a guard rail is lower).
  double side_clearance = 0.25;  ///< m above the ground
  double side_share = 0.5;       ///< of its length, in side_bin pieces
  double side_top = 2.0;         ///< m above the ground
  double side_bin = 0.5;         ///< m along it
  double min_top = 0.5;          ///< m: lower segments are kerbs, verges, debris
  /// m, and m per metre of range: a standing object reaches the ground; the allowance grows
  /// with the gap between scan rings.
  double max_bottom = 0.5;
  double max_bottom_per_m = 0.01;
  /// m: ... unless a nearer object hides its foot from the sensor (the line of sight to its
  /// lowest return passes within hidden_foot_margin over a nearer cell's top: a car seen over
  /// another's roof), up to this; 0: never.
  double max_hidden_bottom = 1.6;
  double hidden_foot_margin = 0.2;  ///< m
  /// m: ... for a segment no taller than a car; a taller one with a hidden foot may be a
  /// hedge or wall behind parked cars, which the vehicle decision would take for a truck.
  double max_hidden_top = 2.2;
  /// deg and m: points whose least-variance direction lies within terrain_angle_deg of
  /// vertical with a spread below terrain_thickness are a raised surface (a ramp, a pavement
  /// edge), not an object.
  double terrain_angle_deg = 30.0;
  double terrain_thickness = 0.08;
  /// m: a footprint diagonal below pole_diagonal reaching above pole_top is a pole, trunk or
  /// sign post (taller than a person).
  double pole_diagonal = 0.7;
  double pole_top = 2.5;
  /// m: anything over the segment's cells higher than this (buildings, tree crowns) is no
  /// vehicle.
  double max_column_top = 4.5;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("min_points", self.min_points, nonNegative("points"));
    visit("max_length", self.max_length, positive("m"));
    visit("max_width", self.max_width, positive("m"));
    visit("max_area", self.max_area, positive("m^2"));
    visit("wall_length", self.wall_length, positive("m"));
    visit("wall_width", self.wall_width, nonNegative("m"));
    visit("side_clearance", self.side_clearance, nonNegative("m"));
    visit("side_share", self.side_share, interval(0, 1, ""));
    visit("side_top", self.side_top, nonNegative("m"));
    visit("side_bin", self.side_bin, atLeast(0.01, "m"));
    visit("min_top", self.min_top, nonNegative("m"));
    visit("max_bottom", self.max_bottom, nonNegative("m"));
    visit("max_bottom_per_m", self.max_bottom_per_m, nonNegative("m/m"));
    visit("max_hidden_bottom", self.max_hidden_bottom, nonNegative("m"));
    visit("hidden_foot_margin", self.hidden_foot_margin, nonNegative("m"));
    visit("max_hidden_top", self.max_hidden_top, nonNegative("m"));
    visit("terrain_angle_deg", self.terrain_angle_deg, interval(0, 90, "deg"));
    visit("terrain_thickness", self.terrain_thickness, nonNegative("m"));
    visit("pole_diagonal", self.pole_diagonal, nonNegative("m"));
    visit("pole_top", self.pole_top, positive("m"));
    visit("max_column_top", self.max_column_top, positive("m"));
  }
};

/// Objects beside a wall: a segment that fails the size or wall gate may be a wall, fence or
/// hedge with a car or a post touching it. Its longest straight run of cells (a Hough search
/// over the cells' centres) at most `thickness` thick, longer than the gates' wall_length and
/// holding at least `min_share` of its cells is taken away, and what is left splits into pieces
/// that go through the gates again, up to `max_walls` times per segment. Slivers of the wall
/// left beside it (its far face, a hedge's fringe) are dropped, and so is a piece thinner than
/// the gates' wall_width within parallel_deg of the wall's direction: more of the same wall
/// where it steps in or out.
struct WallPeeling {
  int max_walls = 1;           ///< walls taken from one segment; 0: none
  double thickness = 0.3;      ///< m, across the wall
  double angle_step_deg = 1.0; ///< deg, of the Hough search over directions
  double parallel_deg = 15.0;  ///< deg
  /// A run holding less of the segment's cells (those not low: ObjectSegmentationConfig::
  /// link_min_top) is part of a building or a row of trees, not a wall with an object beside
  /// it (KITTI: 21 segments peeled in ten frames, 45 without).
  double min_share = 0.35;
  /// Segments of more occupied cells are not searched: a wall with a car beside it is a few
  /// hundred cells (0.15 m), larger ones are buildings and tree rows.
  std::size_t max_cells = 2000;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("max_walls", self.max_walls, interval(0, 10, "walls"));
    visit("thickness", self.thickness, atLeast(0.01, "m"));
    visit("angle_step_deg", self.angle_step_deg, interval(0.01, 45, "deg"));
    visit("parallel_deg", self.parallel_deg, interval(0, 90, "deg"));
    visit("min_share", self.min_share, interval(0, 1, ""));
    visit("max_cells", self.max_cells, nonNegative("cells"));
  }
};

/// Segmentation of real scans without boxes, after the ground stage (config/ground.yaml): the
/// paper's occupancy grid over the points standing above the ground, whose cells join over gaps
/// that grow with range (a rotating LiDAR's returns lie farther apart far away), then the
/// gates, and a box per segment: the footprint's minimum-area rectangle, from the ground to
/// the top.
struct ObjectSegmentationConfig {
  /// m above the ground: the points above the ground stage's ground_height and below
  /// max_height are the candidates; above, overhangs (crowns, awnings) that would join a car
  /// to its tree.
  double max_height = 3.0;
  double min_range = 2.5;    ///< m: nearer points are the sensor's own vehicle ...
  /// ... when also within this many metres of the sensor's x axis: beside it, the side of a
  /// truck passing in the next lane comes nearer than min_range and must stay whole (KITTI's
  /// own returns lie within 1.55 m of that axis).
  double own_half_width = 1.6;
  double max_range = 80.0;   ///< m: the grid covers this around the sensor
  double cell_size = 0.15;   ///< m, the paper's cell
  /// Occupied cells up to link_cells rows or columns apart join (1: touching cells) ...
  int link_cells = 1;
  /// ... or farther: a cell at range r reaches cells up to link_range_steps * r * azimuth_step
  /// (that many times the spacing of returns along a ring there) rows or columns away.
  /// Consecutive returns on a face seen at a slant lie that far apart in range.
  double link_range_steps = 3.3;
  /// Across the line of sight, though, cells farther apart than link_cells join only up to
  /// link_azimuth_steps returns' spacing at their range (and one cell) apart: neighbours along
  /// a ring, not the car parked beside (docs/segmentation.md).
  double link_azimuth_steps = 1.2;
  /// m above the ground: a cell whose points are all lower (a kerb, a verge, the foot of a
  /// hedge, a car's underside) joins the nearest taller cell it would join but links no two
  /// cells, so that a car and the hedge beside it stay apart (0: every cell links).
  double link_min_top = 0.4;
  /// deg: the sensor's angle between returns along a ring (HDL-64E 0.176; the simulator 1).
  double azimuth_step_deg = 0.176;
  SegmentGates gates;
  WallPeeling walls;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("max_height", self.max_height, positive("m"));
    visit("min_range", self.min_range, nonNegative("m"));
    visit("own_half_width", self.own_half_width, nonNegative("m"));
    visit("max_range", self.max_range, positive("m"));
    visit("cell_size", self.cell_size, positive("m"));
    visit("link_cells", self.link_cells, interval(1, 100, "cells"));
    visit("link_range_steps", self.link_range_steps, nonNegative("returns"));
    visit("link_azimuth_steps", self.link_azimuth_steps, nonNegative("returns"));
    visit("link_min_top", self.link_min_top, nonNegative("m"));
    visit("azimuth_step_deg", self.azimuth_step_deg, positive("deg"));
    visit("gates", self.gates);
    visit("walls", self.walls);
  }
};

/// Throws std::invalid_argument naming the field for a value out of range.
void validate(const ObjectSegmentationConfig& config);

/// One frame's segmentation.
struct ObjectSegmentation {
  GroundEstimate ground;  ///< what the segmentation stood on (empty for the occupancy method)
  /// The segments that passed the gates. Segment::indices are the segment's candidate points
  /// (the points above the ground), ascending; the box's bottom is the ground under them.
  std::vector<Segment> segments;
  /// Segments each gate removed, by gate name (first failing gate only); walls taken from
  /// segments (WallPeeling) under "walls_peeled".
  std::map<std::string, std::size_t> rejected;
};

/// Segments cloud after cloud as ObjectSegmentationConfig says, reusing its grids, so that a
/// frame costs what its points cost and not what the grid's size does (the online node and the
/// evaluation keep one).
class ObjectSegmenter {
 public:
  /// Validates `config`.
  explicit ObjectSegmenter(const ObjectSegmentationConfig& config = {});

  /// The segments of `cloud` (sensor frame, z up) standing on `ground` (estimateGround of the
  /// same cloud), in the order of their first cell in a row-major scan of the grid (the
  /// pieces of a segment a wall was peeled from in its place, in the same order among them).
  /// `ground` becomes the result's.
  ObjectSegmentation segment(const Cloud& cloud, GroundEstimate ground);

  const ObjectSegmentationConfig& config() const { return config_; }

 private:
  ObjectSegmentationConfig config_;
  /// Per grid cell: its place among the frame's occupied cells, -1 between frames.
  std::vector<std::int32_t> slot_;
  /// Per grid cell, one bit (rows padded to whole words): whether slot_ holds a place. A
  /// thirty-second of slot_'s size, so that the windows the links scan stay in cache.
  std::vector<std::uint64_t> held_;
};

/// One cloud through the ground stage and a fresh ObjectSegmenter.
ObjectSegmentation segmentObjects(const Cloud& cloud, const GroundConfig& ground = {},
                                  const ObjectSegmentationConfig& config = {});

/// The box-free stage's choice of method.
enum class SegmentationMethod {
  kObjects,    ///< segmentObjects: ground first, range-aware grid, gates (real scans)
  kOccupancy,  ///< segmentCloud: the paper's grid on the whole cloud, as published
};

template <>
struct config::EnumNames<SegmentationMethod> {
  static constexpr const char* what = "segmentation method";
  static constexpr std::array<std::pair<SegmentationMethod, const char*>, 2> values{
      {{SegmentationMethod::kObjects, "objects"}, {SegmentationMethod::kOccupancy, "occupancy"}}};
};

/// config/segmentation.yaml: the method and each method's settings, and what the Background
/// class is made of.
struct SegmentationStageConfig {
  SegmentationMethod method = SegmentationMethod::kObjects;
  ObjectSegmentationConfig objects;
  SegmentationConfig occupancy;
  BackgroundConfig background;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("method", self.method);
    visit("objects", self.objects);
    visit("occupancy", self.occupancy);
    visit("background", self.background);
  }
};

void validate(const SegmentationStageConfig& config);

/// The configured method, cloud after cloud: for the objects method the ground stage
/// (config/ground.yaml) first.
class FrameSegmenter {
 public:
  /// Validates both configurations.
  FrameSegmenter(const GroundConfig& ground, const SegmentationStageConfig& config);
  /// The segments of `cloud`; for the occupancy method, no ground and nothing rejected.
  ObjectSegmentation segment(const Cloud& cloud);

 private:
  GroundConfig ground_;
  SegmentationStageConfig config_;
  ObjectSegmenter objects_;
};

}  // namespace granular
