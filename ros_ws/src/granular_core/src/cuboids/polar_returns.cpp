#include "granular_core/cuboids/polar_returns.h"

#include <cmath>

#include "granular_core/geometry/fast_atan2.h"

namespace granular {

PolarReturns::PolarReturns(const Cloud& cloud, const GroundPlane& ground) : ground_(ground) {
  returns_.reserve(cloud.size());
  for (const PointXYZIT& point : cloud) {
    const Eigen::Vector3d p(point.x, point.y, point.z);
    const double height = ground_.heightOf(p);
    // The height above a finite plane is finite exactly where x, y and z are (0 times
    // infinity is NaN; no float overflows it): one test for three.
    if (!std::isfinite(height)) {
      continue;
    }
    returns_.push_back({fastAtan2(p.y(), p.x()) + M_PI, p.head<2>().norm(), height, point.x,
                        point.y});
  }
}

}  // namespace granular
