// The zero-shot vehicle decision: whether a segment's points and its fitted cuboid look like a
// vehicle's opaque body, from cues that hold for every rotating LiDAR (VehicleEvidenceConfig).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "granular_core/cuboids/cuboid_config.h"
#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/cuboids/polar_returns.h"
#include "granular_core/ground/ground.h"
#include "granular_core/point_types.h"

namespace granular {

/// What a segment showed of itself (VehicleEvidence::measure).
struct VehicleCues {
  std::size_t points = 0;       ///< returns higher than road_height above the road
  std::size_t body_points = 0;  ///< returns between body_min and body_max above the road
  double top = 0.0;             ///< m above the road, the highest return
  double seen_length = 0.0;     ///< m, the points' extent along the cuboid's longer seen axis
  double seen_width = 0.0;      ///< m, across it
  /// m: the returns' span across the line of sight, their azimuth span plus one sensor step,
  /// at their mean range. Every view of a car spans at least its width (a rectangle's shadow
  /// is never narrower than its shorter side).
  double across_sight = 0.0;
  /// Something at most across_hide_depth nearer stands beside it (in its outermost azimuth bins
  /// or the next), hiding its body band there: it may go on behind that (a car in a row).
  bool side_hidden = false;
  /// Of the rays through the body band within the object's azimuth span (its edge bins left
  /// out), the share that returned from behind it.
  double pass_share = 0.0;
  /// Share of the azimuth bins across it holding a body return (an outermost bin without one
  /// not counted).
  double fill = 0.0;
  double face_distance = 0.0;   ///< m, median distance of body returns from the seen faces
  /// Share of the tall_bin pieces along the seen side whose lowest return is above
  /// tall_clearance.
  double clear_share = 0.0;
  /// m: how much lower the top is at the lower end of the longer side seen (its outer
  /// quarters) than in its middle: a car's bonnet or boot against its roof.
  double profile_drop = 0.0;
  /// m, the cuboid's shorter side: the fit grows a box only into space not seen empty, so a
  /// box narrower than a car saw the scan's rays pass behind it.
  double cuboid_width = 0.0;
  /// m, measured for tall objects only (top above max_car_top): how wide the face across the
  /// line of sight is near the top (VehicleEvidenceConfig::end_face_min_width), the rear or
  /// front of a truck or bus seen end on.
  double end_face_width = 0.0;
};

/// Why a segment is no vehicle; kVehicle when it is one.
enum class VehicleVerdict : std::uint8_t {
  kVehicle,
  kTooFewPoints,    ///< min_points, min_body_points
  kTooLow,          ///< min_top
  kTooTall,         ///< max_top
  kTooSmall,        ///< min_extent, min_across_sight
  kTooThin,         ///< min_width: its cuboid is narrower than a car (hedges, shrubs)
  kSeeThrough,      ///< max_pass_share: rays pass through it (foliage)
  kGaps,            ///< min_fill: gaps between its returns (fences, rails, branches)
  kNotASurface,     ///< max_face_distance: returns spread through a volume (bushes)
  kTallOnTheRoad,   ///< taller than max_car_top, standing on the road or no flat box face
  kFlatTop,         ///< a long side with a level top (walls, fences, hedges)
  kOnePlane,        ///< a long side seen as one thin plane, car-high (a wall's face)
  kTooLong,         ///< longer than a car, lower than a truck (hedges, fences)
};

/// The verdict's name, for reports and counts ("vehicle", "see_through", ...).
const char* verdictName(VehicleVerdict verdict);

/// The cues of a frame's objects, measured against that frame's whole scan.
class VehicleEvidence {
 public:
  /// Bins the frame's returns by azimuth about the sensor (the origin) with their heights above
  /// `ground`. `azimuth_step_deg` is the sensor's step between returns along a ring: the bins
  /// are at least twice as wide. Validates nothing: `config` comes from a validated
  /// CuboidConfig.
  VehicleEvidence(const Cloud& cloud, const GroundPlane& ground,
                  const VehicleEvidenceConfig& config, double azimuth_step_deg);
  /// The same from the frame's returns about the sensor, above their road plane (the frame's
  /// FreeSpace reads them too).
  VehicleEvidence(const PolarReturns& scan, const VehicleEvidenceConfig& config,
                  double azimuth_step_deg);

  /// The cues of an object (its points in the sensor frame) and the cuboid fitted to it.
  VehicleCues measure(const std::vector<Eigen::Vector3d>& points, const OrientedBox& cuboid) const;

  /// The verdict on cues measured with this frame's config.
  VehicleVerdict judge(const VehicleCues& cues) const;

 private:
  struct Return {
    float range;   // m, horizontal
    float height;  // m above the ground
  };
  // An object's return: its azimuth bin about the object's direction, range, height above the
  // road and coordinates along the cuboid's length (u) and across it (v).
  struct Seen {
    long bin;
    double range, height, u, v;
  };
  std::size_t binOf(double x, double y) const;
  // The bin of a return at x, y whose fastAtan2 azimuth from -pi is `azimuth`.
  std::size_t binAt(double azimuth, double x, double y) const;
  /// m: the span across the cuboid of the returns within end_face_band of `top` that lie
  /// within end_face_depth of the nearest of them along its length (VehicleCues).
  double endFaceWidth(const std::vector<Seen>& seen, double top) const;

  VehicleEvidenceConfig config_;
  GroundPlane ground_;
  double sensor_height_;  // m above the ground
  double bin_;            // rad
  double step_;           // rad, the sensor's azimuth step
  std::size_t bins_;
  std::size_t min_points_, min_body_points_;  // the config's, for this sensor's step
  std::vector<std::uint32_t> first_;  // per bin, its first return in returns_ (bins_ + 1)
  std::vector<Return> returns_;       // by bin
};

}  // namespace granular
