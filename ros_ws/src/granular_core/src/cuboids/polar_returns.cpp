#include "granular_core/cuboids/polar_returns.h"

#include <cmath>

#include "granular_core/geometry/fast_atan2.h"

namespace granular {

PolarReturns::PolarReturns(const Cloud& cloud, const GroundPlane& ground) : ground_(ground) {
  returns_.reserve(cloud.size());
  for (const PointXYZIT& point : cloud) {
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z)) {
      continue;
    }
    const Eigen::Vector3d p(point.x, point.y, point.z);
    returns_.push_back({fastAtan2(p.y(), p.x()) + M_PI, p.head<2>().norm(), ground_.heightOf(p),
                        point.x, point.y});
  }
}

}  // namespace granular
