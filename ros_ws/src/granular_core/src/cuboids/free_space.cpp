#include "granular_core/cuboids/free_space.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "granular_core/geometry/fast_atan2.h"

namespace granular {

// Inline: the constructor calls both for each of a frame's 120,000 returns.
inline std::optional<std::size_t> FreeSpace::cellOf(double x, double y) const {
  const double half = static_cast<double>(side_ / 2);
  const double column = std::floor(x / cell_) + half, row = std::floor(y / cell_) + half;
  if (side_ == 0 || column < 0.0 || row < 0.0 || column >= static_cast<double>(side_) ||
      row >= static_cast<double>(side_)) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(row) * side_ + static_cast<std::size_t>(column);
}

inline std::size_t FreeSpace::binAt(double azimuth) const {
  // The angle lies in [0, 2 pi], so the bin is at most one past the last: a comparison wraps
  // it, sparing each return of the scan an integer division.
  const auto bin = static_cast<std::size_t>(azimuth / bin_);
  return bin < blocked_.size() ? bin : bin % blocked_.size();
}

inline std::size_t FreeSpace::binOf(double x, double y) const {
  return binAt(fastAtan2(y, x) + M_PI);
}

FreeSpace::FreeSpace(const Cloud& cloud, const GroundPlane& ground, const FreeSpaceConfig& config)
    : FreeSpace(PolarReturns(cloud, ground), config) {}

FreeSpace::FreeSpace(const PolarReturns& scan, const FreeSpaceConfig& config)
    : bin_(config.bin_deg * M_PI / 180.0),
      cell_(config.occupied_cell),
      side_(cell_ > 0.0 ? 2 * static_cast<std::size_t>(std::ceil(config.occupied_range / cell_))
                        : 0) {
  if (bin_ <= 0.0) {
    return;
  }
  // A bit per cell: setting and testing cost a shift, where a sorted list of the frame's cells
  // cost KITTI's 120,000-point frames 2 ms.
  occupied_.assign((side_ * side_ + 63) / 64, 0);
  const std::size_t bins = static_cast<std::size_t>(std::ceil(2.0 * M_PI / bin_));
  blocked_.assign(bins, std::numeric_limits<float>::infinity());
  reach_.assign(bins, 0.0f);
  const double sensor_height = scan.ground().heightOf(Eigen::Vector3d::Zero());
  for (const PolarReturns::Return& r : scan.returns()) {
    const double height = r.height;
    if (height > config.body_max) {
      continue;  // above the band: neither blocks it nor tells how far it was seen
    }
    const std::size_t bin = binAt(r.azimuth);
    float reach = 0.0f;
    if (height >= config.body_min) {
      blocked_[bin] = std::min(blocked_[bin], static_cast<float>(r.range));
      reach = static_cast<float>(r.range);
      if (const std::optional<std::size_t> cell = cellOf(r.x, r.y)) {
        occupied_[*cell / 64] |= std::uint64_t{1} << (*cell % 64);
      }
    } else if (sensor_height > config.body_min) {
      // The ray came down from the sensor to the road: it was in the band until here.
      reach = static_cast<float>(r.range * (sensor_height - config.body_min) /
                                 (sensor_height - height));
    }
    reach_[bin] = std::max(reach_[bin], reach);
  }
}

bool FreeSpace::seenEmpty(const Eigen::Vector3d& point) const {
  if (blocked_.empty() || !point.allFinite()) {
    return false;
  }
  const double range = point.head<2>().norm();
  const std::size_t bin = binOf(point.x(), point.y());
  return blocked_[bin] > range && reach_[bin] > range;
}

bool FreeSpace::seenOccupied(const Eigen::Vector3d& point) const {
  if (occupied_.empty() || !point.allFinite()) {
    return false;
  }
  const std::optional<std::size_t> cell = cellOf(point.x(), point.y());
  return cell && (occupied_[*cell / 64] >> (*cell % 64) & 1u) != 0;
}

}  // namespace granular
