// What a scan saw of the space around its sensor: where rays passed at a vehicle's body height
// without a return. The geometric fitter grows a partly seen object only into space not seen
// empty (a car whose whole side was seen keeps its own length, whatever its class's mean).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "granular_core/cuboids/cuboid_config.h"
#include "granular_core/cuboids/polar_returns.h"
#include "granular_core/ground/ground.h"
#include "granular_core/point_types.h"

namespace granular {

/// Per azimuth bin about the sensor (the sensor frame's origin, its z the sensor's up): the
/// nearest return within the body band above the ground (it blocks the rays behind it), and how
/// far rays were seen to pass within the band: to a return in the band, or, for a return below
/// it (the road), as far as its ray stayed in the band on its way down from the sensor.
class FreeSpace {
 public:
  FreeSpace(const Cloud& cloud, const GroundPlane& ground, const FreeSpaceConfig& config);
  /// The same from the frame's returns about the sensor, above their road plane.
  FreeSpace(const PolarReturns& scan, const FreeSpaceConfig& config);

  /// Whether rays were seen to pass over `point` (sensor frame; its x, y) within the body band
  /// with nothing nearer in the band: the place is empty at body height. False where the scan
  /// says nothing (no return beyond it, or one nearer).
  bool seenEmpty(const Eigen::Vector3d& point) const;

  /// Whether a return within the body band lies in the occupied_cell square around `point`
  /// (sensor frame; its x, y) within occupied_range of the sensor: something stands there.
  bool seenOccupied(const Eigen::Vector3d& point) const;

 private:
  // The azimuth bin of x, y (the sensor frame's), and of an azimuth in [0, 2 pi] from -pi.
  std::size_t binOf(double x, double y) const;
  std::size_t binAt(double azimuth) const;

  double bin_;  // rad
  std::vector<float> blocked_;  // m, nearest return in the band
  std::vector<float> reach_;    // m, farthest a ray was seen to pass within the band
  // The cell of x, y in occupied_, or none beyond the grid.
  std::optional<std::size_t> cellOf(double x, double y) const;

  double cell_;       // m, of the occupied cells
  std::size_t side_;  // cells along each side of the square grid centred on the sensor
  std::vector<std::uint64_t> occupied_;  // one bit per cell: it holds a return in the band
};

}  // namespace granular
