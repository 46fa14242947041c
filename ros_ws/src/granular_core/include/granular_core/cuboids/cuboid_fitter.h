#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "granular_core/cuboids/cuboid_config.h"
#include "granular_core/cuboids/free_space.h"
#include "granular_core/dataset/models_folder.h"
#include "granular_core/geometry/oriented_box.h"
#include "granular_core/ground/ground.h"

namespace granular {

/// One object as the fitters see it.
struct ObjectView {
  /// The object's points in the sensor frame, metres. Road returns may be among them: the
  /// fitters keep the points between ObjectPointsConfig::min_height and max_height above the
  /// ground.
  std::vector<Eigen::Vector3d> points;
  /// The road under the object. Unset: a flat road (normal z) through the object's lowest
  /// point, and every point below max_height above it is kept.
  std::optional<GroundPlane> ground;
  /// m above the ground: where the points were cut (a segmentation's max_height, against
  /// overhangs), so that an object reaching it may be taller. Unset: none.
  std::optional<double> height_cap;
  /// The sensor's position in the sensor frame (the origin, for a frame's own cloud): the
  /// faces turned to it are the ones seen.
  Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
  /// What the scan around the object saw empty (its frame's FreeSpace, from a sensor at the
  /// origin): the geometric fit grows no box into it. Null: nothing is known to be empty.
  const FreeSpace* free_space = nullptr;
  /// rad about the sensor frame's z, modulo pi: the heading the object's length lies along,
  /// where its own points leave it open (NeighbourHeadingConfig). The geometric fit takes it
  /// instead of the L-shape's; unset: the points decide.
  std::optional<double> heading;
};

/// A fitted cuboid.
struct FittedCuboid {
  /// The class: the best model's label (model-based), "unknown" (geometric).
  std::string label;
  /// exp(-fitness / score_scale) of the best model (model-based); 1 (geometric).
  double score = 1.0;
  /// Centre, orientation (yaw about the ground's normal, roll and pitch from the ground) and
  /// size (length along the heading, width, height); bottom face on the ground.
  OrientedBox box;
  /// Object points the fit used (after the height filter).
  std::size_t points = 0;
  /// Whether the points showed the length axis (seen longer than the class is wide, or the
  /// model fit's registration); false where the fit chose it between two open ones.
  bool heading_seen = true;
};

/// The object of a detection among `points` (sensor frame; those in its box grown by
/// detections.margin), as DetectionPointsConfig says: of the points within the height band of
/// config.points above `ground` (all of them, without one), the bird's-eye clusters
/// (cells of detections.cluster_gap, touching cells joined) of which more than half the points
/// lie within hypot(size.x, size.y) / 2 of `centre` (x-y); the cluster with most points there
/// when none does. `size` is the detection's; its heading is not used.
std::vector<Eigen::Vector3d> isolateObject(const std::vector<Eigen::Vector3d>& points,
                                           const std::optional<GroundPlane>& ground,
                                           const Eigen::Vector3d& centre,
                                           const Eigen::Vector3d& size,
                                           const CuboidConfig& config);

/// Fits a cuboid to an object's points; one object at a time, safe to call from several
/// threads at once.
class CuboidFitter {
 public:
  virtual ~CuboidFitter() = default;
  /// The cuboid of `object`; nullopt when fewer than ObjectPointsConfig::min_points points are
  /// left after the height filter.
  virtual std::optional<FittedCuboid> fit(const ObjectView& object) const = 0;
};

/// The label of a geometric fit.
inline constexpr const char* kUnknownLabel = "unknown";

/// Geometric fitting. In the frame levelled on the ground (normal = z): the L-shape rectangle
/// of the points seen from above (fitLShape, over points thinned to one per lshape.cell), then
/// the size prior of the class in geometric.classes whose height is nearest the object's
/// highest point; when that point is at the object's height_cap (the segmentation cut the
/// object there), the shortest prior at least that high that is longer than the seen length.
/// Which rectangle axis is the length, judged on the extents of the object's upper half (its
/// body, not the wheels seen below it): the longer extent when it exceeds the prior's width by
/// width_tolerance or both are within width_tolerance of it; otherwise the other axis than the
/// one whose extent is nearer the prior's width (a rear face, or a side seen edge on). Each extent shorter than the
/// prior's is grown to it away from the sensor: the end of the axis nearer the sensor stays, so
/// the nearest corner (or face) stays where it was seen. Objects smaller than min_extent keep
/// the observed rectangle. The box stands on the ground, as high as the highest point (the
/// prior's height below height_points points).
class GeometricCuboidFitter : public CuboidFitter {
 public:
  /// Validates `config`.
  explicit GeometricCuboidFitter(const CuboidConfig& config);
  std::optional<FittedCuboid> fit(const ObjectView& object) const override;

 private:
  CuboidConfig config_;
};

/// Model-based fitting. The L-shape rectangle as above gives four headings (its two axes, each
/// both ways; model.headings = 2 keeps the length axis the geometric fit would choose). For
/// each heading and class model, the model's box (the extent of its cloud: x and y, and from
/// the road, z = 0 of the object frame, to its top) is placed grown from the seen corner as a
/// size prior would be, the object's points (thinned to one per model.voxel) are moved into
/// that box's object frame, and their fitness to the model (mean squared distance to the
/// nearest model point) is measured there. The model.registered hypotheses of lowest fitness
/// are registered (model.method with model.registration, through RegistrationClassifier); the
/// best is chosen by the report's criteria: among the converged the lowest fitness (criterion
/// 2), else the lowest fitness (criterion 3). The cuboid is the model's box in the registered
/// pose, its yaw about the ground's normal kept and roll and pitch taken from the ground; the
/// label is the model's and the score exp(-fitness / model.score_scale).
class ModelCuboidFitter : public CuboidFitter {
 public:
  /// Validates `config`; throws std::invalid_argument for no models or an empty one (see
  /// RegistrationClassifier).
  ModelCuboidFitter(const CuboidConfig& config, std::vector<LabelledModel> models);
  ~ModelCuboidFitter() override;
  std::optional<FittedCuboid> fit(const ObjectView& object) const override;
  /// The model labels, in label order.
  std::vector<std::string> labels() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The baseline, today's segment box: in the levelled frame, the minimum-area rectangle of the
/// points seen from above (its longer side the length), from the ground to the highest point.
/// Label "unknown", score 1.
class RectangleCuboidFitter : public CuboidFitter {
 public:
  /// Validates `config`.
  explicit RectangleCuboidFitter(const CuboidConfig& config);
  std::optional<FittedCuboid> fit(const ObjectView& object) const override;

 private:
  CuboidConfig config_;
};

/// The fitter config.method names; `models` are for the model-based one, which throws
/// std::invalid_argument without them.
std::unique_ptr<CuboidFitter> makeCuboidFitter(const CuboidConfig& config,
                                               std::vector<LabelledModel> models);

}  // namespace granular
