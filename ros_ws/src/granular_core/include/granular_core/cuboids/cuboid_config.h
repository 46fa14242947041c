#pragma once

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

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("bin_deg", self.bin_deg, interval(0.0, 45.0, "deg"));
    visit("body_min", self.body_min, nonNegative("m"));
    visit("body_max", self.body_max, positive("m"));
    visit("step", self.step, positive("m"));
    visit("inset", self.inset, nonNegative("m"));
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
  }
};

/// Throws std::invalid_argument naming the field for a value out of range, min_height not
/// below max_height, a fine step larger than the coarse one, or a geometric class without a
/// prior.
void validate(const CuboidConfig& config);

}  // namespace granular
