// What the geometric and the model-based fitters share: the object in the frame levelled on
// its ground, its L-shape rectangle, a rectangle grown from the seen corner, and a levelled
// box back in the sensor frame.
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "granular_core/cuboids/cuboid_fitter.h"
#include "granular_core/cuboids/lshape.h"

namespace granular {
namespace cuboids {

/// Per point, its bird's-eye cluster: cells of `gap` (x-y), touching cells (8 neighbours)
/// joined. Clusters are numbered below points.size(), not consecutively.
std::vector<std::size_t> birdsEyeClusters(const std::vector<Eigen::Vector3d>& points,
                                          double gap);

/// An object in the levelled frame: the ground is z = 0 and its normal z.
struct LevelledObject {
  Eigen::Isometry3d levelling = Eigen::Isometry3d::Identity();  ///< sensor frame -> levelled
  std::vector<Eigen::Vector3d> points;  ///< levelled, within the height band
  Eigen::Vector2d sensor = Eigen::Vector2d::Zero();  ///< the sensor's x, y, levelled
  double top = 0.0;                                   ///< m, the highest point's z
  double range = 0.0;  ///< m, from the sensor to the nearest point, seen from above
};

/// m: the larger of `metres` and what `degrees` span, seen from the sensor, at `range` m (a
/// scan's rings and returns spread apart with range).
double spanAt(double range, double metres, double degrees);

/// The object levelled on its ground (ObjectView says which) and its points within the height
/// band of `config`, without an overhang over it; nullopt with fewer than config.min_points
/// points.
std::optional<LevelledObject> levelObject(const ObjectView& object,
                                          const ObjectPointsConfig& config);

/// Per bearing bin of `step_deg` seen from `sensor`, the nearest of `points`: the outline a
/// 2-D scan of them would give.
std::vector<Eigen::Vector2d> outline(const std::vector<Eigen::Vector2d>& points,
                                     const Eigen::Vector2d& sensor, double step_deg);

/// The L-shape rectangle of the levelled points seen from above, searched over their outline
/// as the sensor sees it or over the points thinned to one per config.cell (LShapeConfig), and
/// enclosing them all.
AxisRectangle lshapeRectangle(const LevelledObject& object, const LShapeConfig& config);

/// The rectangle at `heading` (rad, levelled) enclosing the levelled points seen from above.
AxisRectangle enclosingRectangle(const LevelledObject& object, double heading);

/// The extents along `rectangle`'s axes of the points of `object` at least `height` m high;
/// the rectangle's own extents when none are there.
Eigen::Vector2d extentAbove(const LevelledObject& object, const AxisRectangle& rectangle,
                            double height);

/// extentAbove a third of the top: the object's body, without the wheels and the underside
/// seen below it, which would make a rear face look deep.
Eigen::Vector2d bodyExtent(const LevelledObject& object, const AxisRectangle& rectangle);

/// m: how much shorter than the object a face across the line of sight may look, because the
/// scan sampled it: its ends may lie up to one return spacing beyond the outermost returns on
/// either side (twice the median bearing step between the object's returns, seen from the
/// sensor, at its range; 0 with fewer than two bearings). A truck 49 m away on the simulator's
/// 1 degree scan shows its 2.3 m front as three columns of returns 1.6 m apart.
double acrossShortfall(const LevelledObject& object);

/// Which axis of a rectangle of extents `seen` (0: u, 1: v) is the length of an object whose
/// width is `width`, seen along `sight` (the direction from the sensor to the object, in the
/// rectangle's u, v): the longer when it exceeds `width` by more than `tolerance` (it can only
/// be a side); when both are within `tolerance` of `width`, the one nearer the line of sight
/// (an object seen end on, its roof or bonnet seen in depth); otherwise the other axis than the
/// one whose extent is nearer `width` (a face as wide as the class is its front or rear; a face
/// seen edge on is the side). The extent across the line of sight counts as up to
/// `across_shortfall()` m longer than seen (acrossShortfall), asked only when that decides.
int lengthAxis(const Eigen::Vector2d& seen, double width, double tolerance,
               const Eigen::Vector2d& sight,
               const std::function<double()>& across_shortfall = nullptr);

/// Whether a place (levelled x, y) was seen empty at body height.
using SeenEmpty = std::function<bool(const Eigen::Vector2d&)>;

/// How many places the box `grownFromSeenCorner` would give (without `seen_empty`) holds
/// beyond `rectangle` that `refutes`, counted up to `enough` (the count stops there): places on
/// a grid of `step` from `step` beyond the seen ends, up to the grown ends. A vehicle's hidden
/// body can be neither seen empty nor hold another object's returns.
std::size_t refutedGrowth(const AxisRectangle& rectangle, const Eigen::Vector2d& sensor,
                          int length_axis, double length, double width,
                          const std::function<bool(const Eigen::Vector2d&)>& refutes,
                          double step,
                          std::size_t enough = std::numeric_limits<std::size_t>::max());

/// `rectangle` with its extent along axis `length_axis` (0: u, 1: v) grown to at least `length`
/// and along the other to at least `width`, each away from the sensor: the end nearer `sensor`
/// stays. With `seen_empty`, a face seen over at least half of what it grows to stops short of
/// the first place seen empty, tested every `step` beyond its seen end, `inset` behind the face
/// turned to the sensor.
AxisRectangle grownFromSeenCorner(AxisRectangle rectangle, const Eigen::Vector2d& sensor,
                                  int length_axis, double length, double width,
                                  const SeenEmpty& seen_empty = nullptr, double step = 0.25,
                                  double inset = 0.25);

/// The box standing on the levelled ground (z = 0) centred over `centre` (levelled x, y), its
/// length axis at `yaw` (rad) about the ground's normal, of `size`, in the sensor frame.
OrientedBox sensorBox(const Eigen::Isometry3d& levelling, const Eigen::Vector2d& centre,
                      double yaw, const Eigen::Vector3d& size);

}  // namespace cuboids
}  // namespace granular
