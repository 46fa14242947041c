// A frame's returns about the sensor, as the free space and the vehicle decision read them.
#pragma once

#include <vector>

#include "granular_core/ground/ground.h"
#include "granular_core/point_types.h"

namespace granular {

/// The finite returns of a cloud, in the cloud's order, about the sensor (the sensor frame's
/// origin, its z the sensor's up): each one's azimuth, horizontal range and height above the
/// road plane. FreeSpace and VehicleEvidence both bin a frame's returns by azimuth: built once,
/// this spares the second of them its own pass of atan2, range and height over the 120,000
/// returns of a KITTI frame.
class PolarReturns {
 public:
  struct Return {
    double azimuth;  ///< rad in [0, 2 pi]: fastAtan2(y, x) + pi
    double range;    ///< m, from the sensor seen from above
    double height;   ///< m above the road plane
    float x, y;      ///< m, the sensor frame's (where fastAtan2's error matters)
  };

  PolarReturns(const Cloud& cloud, const GroundPlane& ground);

  const GroundPlane& ground() const { return ground_; }
  const std::vector<Return>& returns() const { return returns_; }

 private:
  GroundPlane ground_;
  std::vector<Return> returns_;
};

}  // namespace granular
