#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "granular_core/config/fields.h"
#include "granular_core/point_types.h"

namespace granular {

/// The road as one plane in the sensor frame: normal . p + offset = 0, the unit normal
/// pointing up (normal.z() > 0), so that normal . p + offset is a point's height above it.
struct GroundPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  double offset = 0.0;  ///< m

  double heightOf(const Eigen::Vector3d& point) const { return normal.dot(point) + offset; }
  /// m: the plane's z straight below (or above) the sensor, at x = y = 0.
  double zUnderSensor() const { return -offset / normal.z(); }
  /// Degrees between the normal and the sensor's z axis.
  double tiltDeg() const;
  /// The rigid motion that levels a cloud (report 004's correction, done as one transform):
  /// the shortest rotation taking the normal to +z, then the shift that puts the plane at
  /// z = 0. Heights above the plane become z.
  Eigen::Isometry3d levelling() const;
};

/// The road plane by RANSAC over the lowest point of each seed cell, then least squares.
/// RANSAC is PCL's SACSegmentation with SACMODEL_PERPENDICULAR_PLANE about the sensor's z axis
/// (its eps angle set explicitly: PCL's default of 0 turns the constraint off). The refinement
/// fits a plane to the means, per refine cell, of the cloud points near the plane: ground
/// returns thin out as 1/r^3, and a fit to raw points follows the first metres.
/// docs/ground.md has the measurements behind the defaults (KITTI's published road planes).
struct GroundPlaneConfig {
  /// m: how high the sensor sits above the road, roughly; only the seed band and the plane
  /// used when no plane is found depend on it. KITTI's HDL-64E sits at 1.73 m.
  double sensor_height = 1.73;
  double seed_cell = 0.5;        ///< m, edge of the cells whose lowest points seed RANSAC
  double seed_min_range = 3.0;   ///< m, seeds' horizontal range from the sensor ...
  double seed_max_range = 40.0;  ///< m, ... up to this
  /// deg: seeds within this of straight ahead (+x); 180 takes them all around. Ahead is where
  /// a vehicle's road is, and where camera-based labels (KITTI's) lie.
  double seed_half_fov_deg = 40.0;
  /// m: seeds must lie lower than -sensor_height + seed_band (roofs and crowns are no road).
  double seed_band = 1.0;
  int ransac_iterations = 200;
  double eps_angle_deg = 10.0;     ///< deg, most a plane's normal may lean from z
  double inlier_distance = 0.10;   ///< m, RANSAC's inliers and the refinement's points
  int refine_passes = 3;
  double refine_cell = 0.5;        ///< m, cells whose point means the refinement fits

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("sensor_height", self.sensor_height, positive("m"));
    visit("seed_cell", self.seed_cell, positive("m"));
    visit("seed_min_range", self.seed_min_range, nonNegative("m"));
    visit("seed_max_range", self.seed_max_range, positive("m"));
    visit("seed_half_fov_deg", self.seed_half_fov_deg, interval(0, 180, "deg", true));
    visit("seed_band", self.seed_band, positive("m"));
    visit("ransac_iterations", self.ransac_iterations, atLeast(1));
    visit("eps_angle_deg", self.eps_angle_deg, interval(0, 90, "deg", true, true));
    visit("inlier_distance", self.inlier_distance, positive("m"));
    visit("refine_passes", self.refine_passes, nonNegative());
    visit("refine_cell", self.refine_cell, positive("m"));
  }
};

/// Heights above a road that is not one plane (Himmelsbach et al. 2010): per azimuth sector,
/// the lowest point of each range bin, joined into lines by increasing range; a line is
/// ground when it is flat enough and continues the ground before it (the first one the road
/// plane). A point's height is above the ground line covering its range in its sector; a
/// sector without one uses the plane.
struct GroundLinesConfig {
  int sectors = 180;            ///< azimuth sectors (2 deg each)
  double bin_size = 0.5;        ///< m, range bins
  double max_range = 80.0;      ///< m, farther points keep their height above the plane
  double max_slope = 0.15;      ///< |dz / dr| of a ground line (8.5 deg)
  double max_rmse = 0.05;       ///< m, root mean square error of a line's points
  /// m: a bin's lowest point joins the current line when within this of its prediction; a
  /// later ground line must start within max_step + 0.02 m per metre of gap of the last one.
  double max_step = 0.20;
  /// m, and m per metre of range: the first ground line of a sector must start within
  /// first_line_tolerance + first_line_tolerance_per_m * r of the plane.
  double first_line_tolerance = 0.4;
  double first_line_tolerance_per_m = 0.05;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("sectors", self.sectors, interval(1, 3600));
    visit("bin_size", self.bin_size, positive("m"));
    visit("max_range", self.max_range, positive("m"));
    visit("max_slope", self.max_slope, nonNegative());
    visit("max_rmse", self.max_rmse, positive("m"));
    visit("max_step", self.max_step, positive("m"));
    visit("first_line_tolerance", self.first_line_tolerance, nonNegative("m"));
    visit("first_line_tolerance_per_m", self.first_line_tolerance_per_m, nonNegative("m/m"));
  }
};

/// How point heights are measured.
enum class GroundModel {
  kPlane,  ///< above the one road plane
  kLines,  ///< above per-sector ground lines (follows slopes, kerbs, pavements)
};

template <>
struct config::EnumNames<GroundModel> {
  static constexpr const char* what = "ground model";
  static constexpr std::array<std::pair<GroundModel, const char*>, 2> values{
      {{GroundModel::kPlane, "plane"}, {GroundModel::kLines, "lines"}}};
};

/// Whether a frame's road is where the sensor's frame puts it: sensor_height below the origin,
/// about level. A cloud in a world or vehicle frame (PandaSet's export) has its road far from
/// there and tilting from frame to frame; segments and cuboids found above it are nonsense.
struct SensorFrameCheckConfig {
  /// m: most the road's z straight under the sensor may differ from -sensor_height.
  double height_tolerance = 1.0;
  /// deg: most the road's normal may lean from the sensor's z axis (a 14% grade under a level
  /// car; RANSAC itself accepts up to plane.eps_angle_deg).
  double max_tilt_deg = 8.0;
  /// deg: with no road near -sensor_height, a plane is sought again under the cloud's lowest
  /// returns, leaning up to this, to tell a cloud in another frame from a wall or an empty view.
  double search_tilt_deg = 45.0;
  /// Seeds a plane must hold to be taken as a road by this check (a wall's foot holds few).
  std::size_t min_inliers = 50;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    using namespace config;
    visit("height_tolerance", self.height_tolerance, positive("m"));
    visit("max_tilt_deg", self.max_tilt_deg, interval(0, 90, "deg", true, true));
    visit("search_tilt_deg", self.search_tilt_deg, interval(0, 90, "deg", true, true));
    visit("min_inliers", self.min_inliers, atLeast(3, "seeds"));
  }
};

/// The ground stage: the plane, then each point's height above the ground. The plane is the
/// default: on the KITTI frames the segmentation finds the same objects with fewer false
/// segments above it than above the lines, in 70% of the time (docs/ground.md).
struct GroundConfig {
  GroundModel model = GroundModel::kPlane;
  GroundPlaneConfig plane;
  GroundLinesConfig lines;
  /// m: points lower than this above the ground are ground.
  double ground_height = 0.2;
  SensorFrameCheckConfig sensor_frame;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("model", self.model);
    visit("plane", self.plane);
    visit("lines", self.lines);
    visit("ground_height", self.ground_height, config::positive("m"));
    visit("sensor_frame", self.sensor_frame);
  }
};

/// Throws std::invalid_argument naming the field for a value out of range.
void validate(const GroundConfig& config);

/// One frame's ground.
struct GroundEstimate {
  GroundPlane plane;
  /// Per point of the cloud, m above the ground (NaN for a non-finite point).
  std::vector<float> heights;
  /// Per point, 1 where its height is below config.ground_height, else 0 (a non-finite point
  /// is not ground). A byte each: a vector<bool> cost a dozen instructions a point to write and
  /// as many to read.
  std::vector<std::uint8_t> ground;
  /// Seeds RANSAC saw and the plane's inliers among them; 0 inliers: no plane was found and
  /// the plane is the flat one at -sensor_height.
  std::size_t seeds = 0;
  std::size_t inliers = 0;
};

/// The road plane of `cloud` (sensor frame, z roughly up); see GroundPlaneConfig.
/// `seeds` and `inliers`, when given, receive RANSAC's counts.
GroundPlane estimateGroundPlane(const Cloud& cloud, const GroundPlaneConfig& config,
                                std::size_t* seeds = nullptr, std::size_t* inliers = nullptr);

/// Heights of the points of `cloud` above per-sector ground lines, `plane` where a sector has
/// none; see GroundLinesConfig. NaN for non-finite points.
std::vector<float> groundLineHeights(const Cloud& cloud, const GroundPlane& plane,
                                     const GroundLinesConfig& config);

/// The whole ground stage on one cloud. Validates `config` first.
GroundEstimate estimateGround(const Cloud& cloud, const GroundConfig& config = {});

/// Why the ground stage found no road in `cloud`, for a warning that names the frame; nullopt
/// when it found a plane (`inliers`, GroundEstimate's, above 0). Without one, heights are taken
/// above a flat plane sensor_height below the sensor, and the frame's segments and cuboids may
/// be nonsense: an empty cloud, a wall filling the view, a cloud not in the sensor's frame (a
/// world frame) or a wrong sensor_height.
std::optional<std::string> groundNotFound(const Cloud& cloud, std::size_t inliers,
                                          const GroundPlaneConfig& config);

/// What the ground stage's result says of a frame (checkGround).
struct GroundCheck {
  enum class Verdict {
    kGround,          ///< a road where the sensor's frame puts it
    kNotFound,        ///< no road (groundNotFound's reasons)
    kNotSensorFrame,  ///< a road, but too far from -sensor_height or too tilted (sensor_frame)
  };
  Verdict verdict = Verdict::kGround;
  std::string problem;  ///< why, for a warning or an error (empty for kGround)
};

/// Judges a frame's ground: `plane` and `inliers` as the ground stage found them in `cloud`,
/// `frame_id` the cloud's frame (named in the problem, with the remedies). With no plane near
/// -sensor_height (fewer than sensor_frame.min_inliers seeds on it), one is sought anywhere
/// under the cloud (sensor_frame.search_tilt_deg): found and out of tolerance, the cloud is in
/// another frame; otherwise, with no plane at all, the frame has no ground (groundNotFound).
GroundCheck checkGround(const Cloud& cloud, const GroundPlane& plane, std::size_t inliers,
                        const GroundConfig& config, const std::string& frame_id);

}  // namespace granular
