#pragma once

#include <vector>

#include <Eigen/Geometry>

namespace granular {

/// ICP-NL's step (report 8.2): the rigid motion that minimises the sum of squared distances
/// between the `source` points it moves and their `target` partners (same length), by
/// Levenberg-Marquardt with analytic Jacobians, in double precision. PCL's
/// TransformationEstimationLM minimises the same sum from the same start (the identity) with
/// numerical Jacobians in float and stops at float's tolerance; this stops when a step moves
/// less than 1e-10 (m, rad). Each iteration costs one pass over the pairs (the 6 x 6 normal
/// equations), where PCL's costs seven (its forward differences) and a QR of the pairs'
/// Jacobian.
Eigen::Isometry3d pointToPointLm(const std::vector<Eigen::Vector3d>& source,
                                 const std::vector<Eigen::Vector3d>& target);

}  // namespace granular
