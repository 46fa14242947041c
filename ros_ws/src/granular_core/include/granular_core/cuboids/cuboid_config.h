#pragma once

// The cuboid fitter's configuration: one struct per stage (L-shape, size priors, object points,
// free space, vehicle split and evidence, the geometric, model and click fits) and CuboidConfig
// over them. (Over 400 lines: each struct keeps its field list beside it, as every config does.)

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "granular_core/config/fields.h"
#include "granular_core/registration/registration_config.h"

namespace granular {

/// The three criteria of the L-shape search (Zhang et al. 2017, "Efficient L-Shape Fitting for
/// Vehicle Detection Using Laser Scanners", section III-B), each scoring a rectangle direction
/// by how the bird's-eye points sit against the rectangle's two nearest edges.
enum class LShapeCriterion {
  kArea,       ///< the smallest enclosing rectangle
  kCloseness,  ///< points close to the two nearest edges (sum of 1 / max(distance, d0))
  kVariance,   ///< the least variance of the points' distances to their nearest edge
};

template <>
struct config::EnumNames<LShapeCriterion> {
  static constexpr const char* what = "L-shape criterion";
  static constexpr std::array<std::pair<LShapeCriterion, const char*>, 3> values{
      {{LShapeCriterion::kArea, "area"},
       {LShapeCriterion::kCloseness, "closeness"},
       {LShapeCriterion::kVariance, "variance"}}};
};

/// The search over rectangle directions theta in [0, 90) degrees: a scan at coarse_step_deg,
/// then a scan at fine_step_deg within one coarse step either side of the best. The paper's
/// input is a 2-D scan: one return per bearing, the object's outline as the sensor sees it.
/// With contour_step_deg set the search sees that too: per bearing bin of that width (from the
/// sensor), the nearest point of the object seen from above, so that its roof, the far side
/// seen through the windows and the inside of the body do not count. 0 searches over every
/// point (thinned to one per `cell`).
struct LShapeConfig {
  LShapeCriterion criterion = LShapeCriterion::kCloseness;
  double coarse_step_deg = 1.0;  ///< deg, the paper's delta
  double fine_step_deg = 0.1;    ///< deg
  /// m, the paper's d0: nearer points count as this near. The paper's 0.01 m suits exact
  /// returns; 0.1 m tolerates a real sensor's noise and mirrors' spread (docs/cuboids.md: KITTI
  /// yaw error median 5.4 -> 3.4 deg, simulator unchanged).
  double closeness_d0 = 0.1;
  /// m: d0 again for an object seen as one face (no longer than its class is wide), whose
  /// bumps (a spare wheel, a rounded nose) stand further out of its end; 0: not refitted.
  double face_closeness_d0 = 0.2;
  /// deg: ... its rectangle is taken where it turns the first at least this far (nearer, the
  /// first criterion's precision on a real sensor's noise wins).
  double face_min_turn_deg = 8.0;
  /// m: bird's-eye points are merged to one per cell of this size before the search, so that a
  /// face hit by many rings does not outweigh one hit by few (and the search costs what the
  /// footprint's outline does, not the point count).
  double cell = 0.05;
  double contour_step_deg = 0.5;  ///< deg; 0: every point

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("criterion", self.criterion);
    visit("contour_step_deg", self.contour_step_deg, interval(0, 10, "deg"));
    visit("coarse_step_deg", self.coarse_step_deg, interval(0.01, 45, "deg"));
    visit("fine_step_deg", self.fine_step_deg, interval(0.01, 45, "deg"));
    visit("closeness_d0", self.closeness_d0, positive("m"));
    visit("face_closeness_d0", self.face_closeness_d0, nonNegative("m"));
    visit("face_min_turn_deg", self.face_min_turn_deg, interval(0, 45, "deg"));
    visit("cell", self.cell, positive("m"));
  }
};

/// A class's typical size, metres: length along its heading, width, height.
struct SizePrior {
  double length = 1.0;
  double width = 1.0;
  double height = 1.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    // At most the largest box the tools take (extraction's max_box_size).
    visit("length", self.length, interval(0, 30, "m", true));
    visit("width", self.width, interval(0, 30, "m", true));
    visit("height", self.height, interval(0, 30, "m", true));
  }
};

/// The size priors shipped in code (config/cuboids.yaml repeats them): KITTI's mean Car, Van
/// and Truck, and the simulator's vehicle classes at their meshes' sizes.
std::map<std::string, SizePrior> defaultSizePriors();

/// Which points of an object the fitters use.
struct ObjectPointsConfig {
  /// m above the ground: lower points are the road (and kerbs) under and around the object.
  double min_height = 0.3;
  /// m above the ground: higher points (crowns, signs over the road) are no vehicle.
  double max_height = 4.5;
  /// Objects with fewer points above the ground get no cuboid.
  std::size_t min_points = 3;
  /// Overhangs (a branch or sign over a parked car): points above a gap in height wider than
  /// `overhang_gap` m and than `overhang_gap_deg` as seen from the sensor (the scan's rings
  /// spread apart with range) are left out, when they are at most `overhang_share` of the
  /// object's points (a roof seen over windows that returned nothing is more).
  double overhang_gap = 0.3;
  double overhang_gap_deg = 1.5;
  double overhang_share = 0.05;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("min_height", self.min_height, any("m"));
    visit("max_height", self.max_height, positive("m"));
    visit("min_points", self.min_points, atLeast(3, "points"));
    visit("overhang_gap", self.overhang_gap, positive("m"));
    visit("overhang_gap_deg", self.overhang_gap_deg, interval(0.0, 90.0, "deg", false, true));
    visit("overhang_share", self.overhang_share, fraction());
  }
};

/// What the scan saw around an object (FreeSpace): a box grows from the seen corner only into
/// space the sensor did not see empty, so a car whose whole side was seen keeps its length.
struct FreeSpaceConfig {
  /// deg, the width of the azimuth bins about the sensor; 0: the space is not looked at and a
  /// box always grows to its prior.
  double bin_deg = 0.5;
  /// m above the ground: the band a vehicle's body fills. A return in it blocks its ray; a
  /// ray seen empty over a place passed it within the band.
  double body_min = 0.5;
  double body_max = 2.0;
  /// m: the growth is tested in steps of this beyond the seen end, ...
  double step = 0.25;
  /// m: ... this far behind the face turned to the sensor (the face's rectangle edge is its
  /// outermost returns; nearer the face, a place beside the object is taken for its end).
  double inset = 0.25;
  /// m: the side of the square cells that hold a return within the band (another object
  /// stands there); 0: not looked at.
  double occupied_cell = 0.2;
  double occupied_range = 80.0;  ///< m: the cells cover this far around the sensor
  /// Places (a grid of `step`): an object seen no longer than its class is wide takes its
  /// length along the other side than lengthAxis chose when its body grown along the chosen one
  /// covers at least this many more places seen empty or holding another object's returns (a
  /// car seen end on among parked cars); 0: the sides seen decide alone.
  std::size_t refuted_margin = 1;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("bin_deg", self.bin_deg, interval(0.0, 45.0, "deg"));
    visit("body_min", self.body_min, nonNegative("m"));
    visit("body_max", self.body_max, positive("m"));
    visit("step", self.step, atLeast(0.01, "m"));
    visit("inset", self.inset, nonNegative("m"));
    visit("occupied_cell", self.occupied_cell, nonNegative("m"));
    visit("occupied_range", self.occupied_range, interval(1.0, 200.0, "m"));
    visit("refuted_margin", self.refuted_margin, nonNegative("places"));
  }
};

/// Touching parked cars (splitVehicles): a segment wider or longer than one car and no taller
/// than one is cut at the valleys of its height profile, between roofs or in the gap between
/// two cars' bodies, before each piece is fitted.
struct VehicleSplitConfig {
  bool enabled = true;
  /// m: a footprint wider than a car with its mirrors (side by side) is looked at across its
  /// width, then along its length (cars side by side seen from their fronts make the row the
  /// longer side) ...
  double max_width = 2.0;
  double max_length = 5.6;   ///< m: ... and one longer (nose to tail) along its length
  double max_top = 2.2;      ///< m: taller objects (trucks, buses) are not cut
  double bin = 0.15;         ///< m, of the height profile
  double min_piece = 1.2;    ///< m: no cut leaves a piece narrower than a car seen end on
  double min_drop = 0.35;    ///< m: a valley at least this far below the tops on both sides
  /// m: empty bins count as a valley (the gap between two bodies) only over this length at
  /// least; shorter runs are the spacing between the scan's returns.
  double min_gap = 0.3;
  /// deg: a footprint wider than a car whose width runs within this of the line of sight is
  /// cut along its length first where both show a valley (successive rings spread apart over
  /// roofs and bonnets leave valleys inside one car along the line of sight); 0: width first.
  double sight_gap_deg = 45.0;
  double road_height = 0.2;  ///< m: lower returns are the road
  int max_cuts = 4;          ///< cuts per segment, the deepest first
  /// deg: where neither side of the footprint's rectangle shows a valley, directions this far
  /// apart are searched (two cars seen at a slant); 0: the rectangle's sides only.
  double search_step_deg = 5.0;
  /// m: ... for a footprint wider than this (single cars seen at a slant show valleys across
  /// their diagonals) or longer than max_length; one wider than max_width but not than this is
  /// cut there only at a run of empty bins (the ground between two bodies).
  double search_min_width = 2.3;
  /// m: a footprint whose rectangle along its L-shape's edges is wider than this is cut along
  /// that rectangle's axes, not its minimum-area rectangle's (the L-shapes of cars seen in part
  /// make minimum-area rectangles turned across them); 0: off.
  double edges_min_width = 2.3;
  /// m: a footprint no wider than a car (max_width), longer than this and no longer than
  /// max_length, where no valley was found above, is cut along its length at a run of empty
  /// bins only: longer than min_gap and than twice the scan's spacing between columns there,
  /// with rays seen to pass through it at body height (FreeSpace), and leaving at least
  /// gap_min_points returns on either side. The fronts of two cars parked side by side seen as
  /// one face (one car seen along its side may show an empty run too, between the rings over
  /// its roof or in the sparse far part of its side: hence the two tests); 0: off.
  double gap_min_length = 3.6;
  std::size_t gap_min_points = 50;  ///< points on either side of such a cut, at the least

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("enabled", self.enabled);
    visit("max_width", self.max_width, positive("m"));
    visit("max_length", self.max_length, positive("m"));
    visit("max_top", self.max_top, positive("m"));
    visit("bin", self.bin, atLeast(0.01, "m"));
    visit("min_piece", self.min_piece, positive("m"));
    visit("min_drop", self.min_drop, nonNegative("m"));
    visit("min_gap", self.min_gap, nonNegative("m"));
    visit("sight_gap_deg", self.sight_gap_deg, interval(0.0, 90.0, "deg"));
    visit("road_height", self.road_height, nonNegative("m"));
    visit("max_cuts", self.max_cuts, interval(0, 16, "cuts"));
    visit("search_step_deg", self.search_step_deg, interval(0.0, 90.0, "deg"));
    visit("search_min_width", self.search_min_width, positive("m"));
    visit("edges_min_width", self.edges_min_width, nonNegative("m"));
    visit("gap_min_length", self.gap_min_length, nonNegative("m"));
    visit("gap_min_points", self.gap_min_points, nonNegative("points"));
  }
};

/// The zero-shot vehicle decision on a segment's cuboid (VehicleEvidence): geometry every
/// rotating LiDAR shows, so it needs no labels of the sensor. A vehicle's body is an opaque
/// shell: between body_min and body_max above the road its returns lie on the faces turned to
/// the sensor, they fill every azimuth bin across it, and no ray passes through it to return from
/// behind. Foliage, hedges and tree crowns let rays through and return from inside their volume;
/// fences and posts leave gaps between their returns (docs/cuboids.md measures each cue).
struct VehicleEvidenceConfig {
  bool enabled = true;           ///< false: every segment gets a cuboid (today's behaviour)
  double road_height = 0.2;      ///< m: lower returns are the road under and around it
  double body_min = 0.5;         ///< m above the road: the band where a car's body is solid
  double body_max = 1.0;         ///< m (above it, glass lets rays through)
  /// deg: azimuth bins of the cues; at least twice the sensor's step between returns
  /// (the tools take the larger of this and twice the sensor's azimuth step).
  double bin_deg = 0.4;
  /// m: a return farther than the object's farthest body return in its bin, by this, whose
  /// ray crossed the object's range inside the body band, passed through the object.
  double pass_margin = 0.3;
  /// Most of the object's body rays that may pass through it (returns behind / body returns
  /// and those together).
  double max_pass_share = 0.15;
  /// Least share of the azimuth bins across the object that hold a body return (an outermost
  /// bin without one not counted: a sparse sensor's wide bin may hold only a mirror there).
  double min_fill = 0.85;
  /// The median body return may lie at most max_face_share of the seen width (within
  /// min_face_allowance and max_face_distance, m) from the two faces of the cuboid turned to
  /// the sensor (its L): a car's skin is a surface, a bush's returns spread through its volume.
  double max_face_share = 0.2;
  double min_face_allowance = 0.15;  ///< m
  double max_face_distance = 0.35;   ///< m
  /// Returns above the road and in the body band: fewer cannot be judged. Counted for a sensor
  /// with returns points_reference_step_deg apart along a ring; a sparser one needs
  /// proportionally fewer.
  std::size_t min_points = 30;
  std::size_t min_body_points = 20;
  double points_reference_step_deg = 0.2;  ///< deg
  double min_top = 0.8;          ///< m: lower objects are kerbs, verges, low walls
  double min_extent = 1.0;       ///< m: the longer side seen; shorter are posts and people
  /// m: an object seen narrower across the line of sight (VehicleCues::across_sight) is no car,
  /// which shows at least its width from any side: a shrub, a post, a wall's end (0: off) ...
  double min_across_sight = 1.5;
  /// m: ... unless something at most this much nearer stands beside it, which may hide the rest
  /// (a car in a row of parked cars, its neighbour's front a car's width nearer at a slant).
  double across_hide_depth = 2.5;
  /// m: a cuboid narrower (its shorter side, after growing only into space not seen empty) is
  /// a hedge, shrub or fence whose far side the scan saw; cars are 1.6 m wide and more.
  double min_width = 1.5;
  /// m: taller than this is no car; it is kept only as a truck or bus, whose body stands clear
  /// of the road (below).
  double max_car_top = 2.2;
  double max_top = 4.2;          ///< m: no road vehicle is taller
  double max_car_length = 5.5;   ///< m: a longer side is no car ...
  /// m: ... and is kept only as a truck or bus at least this tall (box trucks and buses stand
  /// about 3 m): lower, it is a hedge, a fence or a wall, whose top may pass max_car_top.
  double min_long_top = 2.6;
  /// m: a tall object's body returns lie this near its faces: a truck's box or a bus's side is
  /// flat (a hedge or a tree row is not).
  double tall_max_face_distance = 0.1;
  /// m above the road: a tall object's band where its body is solid, over the wheels and the
  /// gap under a box truck's cargo box.
  double tall_body_min = 1.2;
  double tall_body_max = 2.5;
  /// A tall object must show, along the side seen, the road under its body: in at least
  /// tall_clear_share of its tall_bin pieces the lowest return is above tall_clearance plus
  /// tall_clearance_per_m per metre of range (the gap between rings grows with range), where a
  /// wall, a building or a tree row reaches the road.
  double tall_clearance = 0.25;  ///< m
  double tall_clearance_per_m = 0.01;  ///< m/m
  double tall_clear_share = 0.5;
  double tall_bin = 0.5;         ///< m
  /// A car's side seen over at least profile_min_length shows its bonnet or boot lower than
  /// its roof: the top of its outer quarters at least min_profile_drop below its middle's, in
  /// pieces of profile_bin (a wall, a fence or a hedge has a level top). 0 by default: only a
  /// side whose ends stand higher than its middle is refused; 0.2 m gained 0.012 of F1 on the
  /// simulated road but cost 0.14 on a simulated parking lot, whose rows of cars show level
  /// tops from the mast (docs/cuboids.md).
  double profile_min_length = 2.5;  ///< m
  double min_profile_drop = 0.0;    ///< m
  double profile_bin = 0.4;         ///< m
  /// A car-high object (top at most max_car_top) seen along a side of profile_min_length or
  /// more shows returns spread at least min_seen_width across that side: the sills, windows and
  /// mirrors of a car's curved flank, its roof or an end. Returns within a thinner band are
  /// one plane, a wall's or a fence's face (the fit still grows its cuboid to a car's width
  /// into the unseen space behind it).
  double min_seen_width = 0.15;     ///< m
  /// A truck or bus seen end on (an object at least min_long_top tall seen no longer than
  /// end_on_max_length) shows its rear or front as a face across the line of sight, as wide as
  /// the vehicle up to its roof: its returns within end_face_band of its top that lie within end_face_depth of the
  /// nearest of them along the cuboid's length span at least end_face_min_width across it.
  /// Such an object is not refused for its clearance or the flatness of its faces (its wheels
  /// and bumper hide the road under it; a cab seen in front of its box is a face nearer than
  /// the box's), though its returns must still lie on a surface (max_face_distance): tree
  /// crowns and bushes as tall are rounded, narrower at the top.
  double end_on_max_length = 3.5;   ///< m
  double end_face_band = 0.4;       ///< m below the top
  double end_face_depth = 0.2;      ///< m
  double end_face_min_width = 1.6;  ///< m
  /// m: a tall object at least min_long_top tall whose face near the top spans
  /// end_face_min_width (as above) but that was seen longer than end_on_max_length (a truck at
  /// a slant) must still stand clear of the road, but its body returns may lie this far from a
  /// flat face instead of tall_max_face_distance: seen from the front, a truck's cab stands
  /// before its box. 0: tall_max_face_distance for every tall object.
  double box_face_max_distance = 0.25;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("enabled", self.enabled);
    visit("road_height", self.road_height, nonNegative("m"));
    visit("body_min", self.body_min, nonNegative("m"));
    visit("body_max", self.body_max, positive("m"));
    visit("bin_deg", self.bin_deg, interval(0.01, 10.0, "deg"));
    visit("pass_margin", self.pass_margin, nonNegative("m"));
    visit("max_pass_share", self.max_pass_share, fraction());
    visit("min_fill", self.min_fill, fraction());
    visit("max_face_share", self.max_face_share, positive());
    visit("min_face_allowance", self.min_face_allowance, positive("m"));
    visit("max_face_distance", self.max_face_distance, positive("m"));
    visit("min_points", self.min_points, nonNegative("points"));
    visit("min_body_points", self.min_body_points, nonNegative("points"));
    visit("points_reference_step_deg", self.points_reference_step_deg, positive("deg"));
    visit("min_top", self.min_top, nonNegative("m"));
    visit("min_extent", self.min_extent, nonNegative("m"));
    visit("min_across_sight", self.min_across_sight, nonNegative("m"));
    visit("across_hide_depth", self.across_hide_depth, nonNegative("m"));
    visit("min_width", self.min_width, nonNegative("m"));
    visit("max_car_top", self.max_car_top, positive("m"));
    visit("max_top", self.max_top, positive("m"));
    visit("max_car_length", self.max_car_length, positive("m"));
    visit("min_long_top", self.min_long_top, positive("m"));
    visit("tall_max_face_distance", self.tall_max_face_distance, positive("m"));
    visit("tall_body_min", self.tall_body_min, nonNegative("m"));
    visit("tall_body_max", self.tall_body_max, positive("m"));
    visit("tall_clearance", self.tall_clearance, nonNegative("m"));
    visit("tall_clearance_per_m", self.tall_clearance_per_m, nonNegative("m/m"));
    visit("tall_clear_share", self.tall_clear_share, fraction());
    visit("tall_bin", self.tall_bin, atLeast(0.05, "m"));
    visit("profile_min_length", self.profile_min_length, nonNegative("m"));
    visit("min_profile_drop", self.min_profile_drop, nonNegative("m"));
    visit("profile_bin", self.profile_bin, atLeast(0.05, "m"));
    visit("min_seen_width", self.min_seen_width, nonNegative("m"));
    visit("end_on_max_length", self.end_on_max_length, nonNegative("m"));
    visit("end_face_band", self.end_face_band, positive("m"));
    visit("end_face_depth", self.end_face_depth, nonNegative("m"));
    visit("end_face_min_width", self.end_face_min_width, positive("m"));
    visit("box_face_max_distance", self.box_face_max_distance, nonNegative("m"));
  }
};

/// Geometric fitting: the L-shape rectangle, then a size prior that grows it away from the
/// sensor.
struct GeometricFitConfig {
  /// The priors the fit chooses among, by the object's height (the nearest prior height);
  /// each must be in `priors`. Empty: the observed rectangle is kept as it is.
  std::vector<std::string> classes = {"Car", "Van", "Truck"};
  /// m: a face longer than the prior's width plus this is a side (the length axis).
  double width_tolerance = 0.4;
  /// m: objects whose longer observed extent is below this (pedestrians, poles) keep the
  /// observed rectangle: no prior applies.
  double min_extent = 1.0;
  /// A person on foot or on two wheels keeps the observed rectangle too: an object at least
  /// rider_min_top m high whose points above rider_above of its top (the rider's torso, over
  /// a bicycle's wheels and frame) span at most rider_width m along both rectangle axes. No
  /// vehicle is that narrow above its waist: a car's rear or roof spans over a metre.
  double rider_width = 0.8;
  double rider_above = 0.6;
  double rider_min_top = 1.2;
  /// Objects with fewer points get the prior's height instead of their highest point's.
  std::size_t height_points = 10;
  /// An object reaches its height cap (ObjectView::height_cap: it may be taller than seen)
  /// when its top is within cap_reach m of the cap, or within cap_reach_deg seen from the
  /// sensor: the ring above the top may have passed over the cap (the simulator's rings are
  /// 0.66 deg apart, 0.38 m at 33 m; KITTI's about 0.4 deg).
  double cap_reach = 0.1;
  double cap_reach_deg = 0.7;
  /// m: an object taller than this (than any car) whose top is more than cap_reach lower
  /// than the prior nearest it in height is fitted as one that reached its height cap: the sensor's highest ring may
  /// have passed under its roof (the HDL-64E's, 2 degrees up, passes 2.7 m above the road 29 m
  /// away, where a 3.3 m box truck then looked nearest the 3.1 m bus).
  double cut_top_above = 2.2;
  /// Such an object (it may be taller than seen) grown to a prior with a longer one at least as
  /// tall takes the longer one when at least this many free_space.step steps past its grown
  /// far end (beyond the first width_tolerance: a vehicle a little longer than its prior), up
  /// to the longer prior's length, hold a return in the free space's body band across its
  /// width: a bus cut at the height cap and seen end on, whose side goes on past a box truck's
  /// length. Seen at a grazing angle, the side's columns of returns stand metres apart (one
  /// step is evidence). 0: off.
  std::size_t longer_occupied_steps = 1;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("classes", self.classes, text("a class with a prior"));
    visit("width_tolerance", self.width_tolerance, nonNegative("m"));
    visit("min_extent", self.min_extent, nonNegative("m"));
    visit("rider_width", self.rider_width, nonNegative("m"));
    visit("rider_above", self.rider_above, fraction());
    visit("rider_min_top", self.rider_min_top, nonNegative("m"));
    visit("height_points", self.height_points, nonNegative("points"));
    visit("cap_reach", self.cap_reach, nonNegative("m"));
    visit("cap_reach_deg", self.cap_reach_deg, interval(0.0, 90.0, "deg", false, true));
    visit("cut_top_above", self.cut_top_above, nonNegative("m"));
    visit("longer_occupied_steps", self.longer_occupied_steps, nonNegative("steps"));
  }
};

/// Model-based fitting: each class model registered against the object from the L-shape's
/// headings, the best pose by the registration classifiers' criteria.
struct ModelFitConfig {
  RegistrationMethod method = RegistrationMethod::kIcp;
  /// The registration's parameters (config/classification.yaml's layout); the defaults here
  /// pull a model from a hypothesis up to about half a metre off.
  RegistrationClassifierConfig registration = defaultRegistration();
  /// m: object points are thinned to one per voxel of this size before registration.
  double voxel = 0.15;
  /// Headings tried per model: 2 (the L-shape's length axis, both ways), or 4 (the width axis
  /// too, both ways).
  int headings = 4;
  /// Of all heading and model hypotheses, the ones whose fitness before registration is the
  /// lowest are registered; the rest are dropped.
  int registered = 3;
  /// m^2: score = exp(-fitness / score_scale), 1 for a perfect fit.
  double score_scale = 0.01;

  static RegistrationClassifierConfig defaultRegistration();

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("method", self.method);
    visit("registration", self.registration);
    visit("voxel", self.voxel, positive("m"));
    visit("headings", self.headings, interval(2, 4));
    visit("registered", self.registered, atLeast(1));
    visit("score_scale", self.score_scale, positive("m^2"));
  }
};

/// Objects taken from given detection boxes (fit_cuboids --boxes detections): the points in
/// the box grown by `margin` on every side, then the bird's-eye clusters of those above the
/// ground (points closer than cluster_gap join) of which more than half lie within the box's
/// circumscribed circle. The box's heading is not used.
struct DetectionPointsConfig {
  double margin = 1.0;        ///< m
  double cluster_gap = 0.3;   ///< m, bird's-eye

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("margin", self.margin, nonNegative("m"));
    visit("cluster_gap", self.cluster_gap, positive("m"));
  }
};

/// A new box where a user clicked on the cloud (label_cuboids, rviz's Publish Point;
/// fitCuboidAtClick).
struct ClickConfig {
  /// m (x-y): the points around the click whose low heights tell the road's height ...
  double ground_radius = 6.0;
  /// %: ... this percentile of them, so that a few returns below the road do not count.
  double ground_percentile = 5.0;
  /// m (x-y) from the click: no object point is farther (or the class footprint's diagonal,
  /// when longer, so that a click on one end reaches the other).
  double reach = 4.0;
  /// m, bird's-eye: points in touching cells of this size belong to one object.
  double gap = 0.3;
  /// m (x-y): the object is what connects to the points this near the click.
  double seed_radius = 1.5;
  /// Fewer object points: the class's size, on the ground, centred on the click.
  std::size_t min_points = 10;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("ground_radius", self.ground_radius, positive("m"));
    visit("ground_percentile", self.ground_percentile, interval(0, 100, "%"));
    visit("reach", self.reach, positive("m"));
    visit("gap", self.gap, positive("m"));
    visit("seed_radius", self.seed_radius, positive("m"));
    visit("min_points", self.min_points, atLeast(3, "points"));
  }
};

/// The fitting method.
enum class CuboidMethod {
  kGeometric,  ///< L-shape and size priors
  kModel,      ///< class models registered to the points (needs a models folder)
  kRectangle,  ///< the baseline: the points' minimum-area rectangle, as segment boxes are
};

template <>
struct config::EnumNames<CuboidMethod> {
  static constexpr const char* what = "cuboid method";
  static constexpr std::array<std::pair<CuboidMethod, const char*>, 3> values{
      {{CuboidMethod::kGeometric, "geometric"},
       {CuboidMethod::kModel, "model"},
       {CuboidMethod::kRectangle, "rectangle"}}};
};

/// config/cuboids.yaml: everything cuboid fitting reads.
/// Cars parked in a row or driving in a lane stand parallel: a cuboid whose points left its
/// length axis open (seen no longer than its class is wide: a car seen end on, or its roof over
/// another's) takes the heading of the nearest cuboid whose points showed its length.
struct NeighbourHeadingConfig {
  /// m between centres: the nearest vehicle within this whose length was seen lends its
  /// heading (a row's neighbour, or the car in front of one seen over its roof); 0: off.
  double radius = 6.0;
  /// deg: lent only where it turns the cuboid at least this far; smaller turns are the fit's.
  double min_turn_deg = 20.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("radius", self.radius, nonNegative("m"));
    visit("min_turn_deg", self.min_turn_deg, interval(0.0, 90.0, "deg"));
  }
};

struct CuboidConfig {
  CuboidMethod method = CuboidMethod::kGeometric;
  ObjectPointsConfig points;
  DetectionPointsConfig detections;
  LShapeConfig lshape;
  std::map<std::string, SizePrior> priors = defaultSizePriors();
  GeometricFitConfig geometric;
  FreeSpaceConfig free_space;
  ModelFitConfig model;
  ClickConfig click;
  VehicleSplitConfig split;
  VehicleEvidenceConfig evidence;
  NeighbourHeadingConfig neighbour_heading;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("method", self.method);
    visit("points", self.points);
    visit("detections", self.detections);
    visit("lshape", self.lshape);
    visit("priors", self.priors);
    visit("geometric", self.geometric);
    visit("free_space", self.free_space);
    visit("model", self.model);
    visit("click", self.click);
    visit("split", self.split);
    visit("evidence", self.evidence);
    visit("neighbour_heading", self.neighbour_heading);
  }
};

/// Throws std::invalid_argument naming the field for a value out of range, min_height not
/// below max_height, a fine step larger than the coarse one, or a geometric class without a
/// prior.
void validate(const CuboidConfig& config);

}  // namespace granular
