// Touching parked cars: a segment holding two or more cars side by side or nose to tail is cut
// into cars at the valleys of its height profile (VehicleSplitConfig).
#pragma once

#include <vector>

#include "granular_core/cuboids/cuboid_config.h"
#include "granular_core/cuboids/cuboid_fitter.h"

namespace granular {

/// The cars of `object`: the object itself when it is no wider and no longer than one car (or
/// taller than one: a truck or a bus is not cut), otherwise the pieces between the cuts. Along
/// each axis of its footprint's minimum-area rectangle that exceeds one car, the points (above
/// the road) are binned every `bin` metres; a cut goes through the lowest bin (empty, or whose
/// highest return is lowest) that lies at least `min_piece` from either end and at least
/// `min_drop` below the tops on both sides, and the pieces are cut again while they still
/// exceed one car. A footprint whose rectangle along its L-shape's edges (`lshape`) is wider
/// than `edges_min_width` is cut along that rectangle's axes instead (cars seen in part show
/// L-shapes whose minimum-area rectangle lies across them). A footprint no wider than one car
/// but longer than `gap_min_length` (the fronts of two cars side by side) is cut along its
/// length only at empty ground: a run of empty bins wider than the scan's columns are apart,
/// through which the object's free space saw rays pass. Each piece keeps the object's ground,
/// height cap, sensor and free space.
std::vector<ObjectView> splitVehicles(const ObjectView& object, const VehicleSplitConfig& config,
                                      const LShapeConfig& lshape = LShapeConfig());

}  // namespace granular
