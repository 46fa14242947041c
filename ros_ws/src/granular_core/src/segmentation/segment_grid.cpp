#include "segment_grid.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace granular {
namespace segmentation_detail {
namespace {

// The places 0 .. keys.size() - 1 ordered by their key (all below key_count), equal keys in
// place order: a least-significant-digit radix sort, 11 bits a pass.
std::vector<std::uint32_t> stableOrderByKey(const std::vector<std::uint32_t>& keys,
                                            std::size_t key_count) {
  constexpr int kDigitBits = 11;
  constexpr std::uint32_t kDigits = 1u << kDigitBits;
  std::vector<std::uint32_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0u);
  std::vector<std::uint32_t> sorted(keys.size());
  std::vector<std::uint32_t> offset(kDigits);
  for (int shift = 0; shift < 32 && (key_count - 1) >> shift != 0; shift += kDigitBits) {
    std::fill(offset.begin(), offset.end(), 0u);
    for (const std::uint32_t key : keys) {
      ++offset[(key >> shift) & (kDigits - 1)];
    }
    std::uint32_t sum = 0;
    for (std::uint32_t& count : offset) {
      sum += std::exchange(count, sum);
    }
    for (const std::uint32_t place : order) {
      sorted[offset[(keys[place] >> shift) & (kDigits - 1)]++] = place;
    }
    order.swap(sorted);
  }
  return order;
}

}  // namespace

FrameGrid buildFrameGrid(const Cloud& cloud, const GroundEstimate& ground,
                         const ObjectSegmentationConfig& config, const PlaneGrid& grid,
                         std::vector<std::int32_t>& slot, CellBits& held) {
  const std::vector<float>& heights = ground.heights;
  const std::vector<std::uint8_t>& on_ground = ground.ground;
  // Room for every return: growing them cost a frame a megabyte of copying.
  std::vector<std::size_t> candidates;
  candidates.reserve(cloud.size());
  std::vector<std::uint32_t> candidate_cell;
  candidate_cell.reserve(cloud.size());
  std::vector<std::size_t> overhangs;  // higher than candidates, up to 8 m
  const double min_range_sq = config.min_range * config.min_range;
  const double max_range_sq = config.max_range * config.max_range;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float height = heights[i];
    if (on_ground[i] != 0 || !std::isfinite(height)) {
      continue;
    }
    const PointXYZIT& point = cloud[i];
    const double range_sq = double(point.x) * point.x + double(point.y) * point.y;
    const bool own_vehicle =
        range_sq <= min_range_sq && std::abs(point.y) <= config.own_half_width;
    if (own_vehicle || range_sq >= max_range_sq) {
      continue;
    }
    if (height > config.max_height) {
      if (height < 8.0f) {
        overhangs.push_back(i);
      }
      continue;
    }
    if (const auto cell = grid.cellOf(point.x, point.y)) {
      candidates.push_back(i);
      candidate_cell.push_back(static_cast<std::uint32_t>(*cell));
    }
  }
  // Sorting by cell first touches `slot` once a cell and in memory order.
  FrameGrid frame;
  frame.by_cell.resize(candidates.size());
  const std::vector<std::uint32_t> order = stableOrderByKey(candidate_cell, grid.cells());
  for (std::size_t n = 0; n < order.size(); ++n) {
    const std::uint32_t cell = candidate_cell[order[n]];
    if (frame.occupied.empty() || frame.occupied.back() != cell) {
      slot[cell] = static_cast<std::int32_t>(frame.occupied.size());
      held.set(cell);
      frame.occupied.push_back(cell);
      frame.start.push_back(static_cast<std::uint32_t>(n));
    }
    frame.by_cell[n] = candidates[order[n]];
  }
  frame.start.push_back(static_cast<std::uint32_t>(order.size()));

  const std::size_t cells = frame.occupied.size();
  frame.top_of_cell.assign(cells, 0.0f);
  frame.low.resize(cells);
  for (std::size_t k = 0; k < cells; ++k) {
    for (std::uint32_t c = frame.start[k]; c < frame.start[k + 1]; ++c) {
      frame.top_of_cell[k] = std::max(frame.top_of_cell[k], heights[frame.by_cell[c]]);
    }
    frame.low[k] = frame.top_of_cell[k] < config.link_min_top ? 1 : 0;
  }
  for (const std::size_t i : overhangs) {
    if (const auto cell = grid.cellOf(cloud[i].x, cloud[i].y); cell && slot[*cell] >= 0) {
      float& top = frame.top_of_cell[static_cast<std::size_t>(slot[*cell])];
      top = std::max(top, heights[i]);
    }
  }
  frame.centre.resize(cells);
  frame.range.resize(cells);
  for (std::size_t k = 0; k < cells; ++k) {
    frame.centre[k] = Eigen::Vector2d(grid.centre(static_cast<int>(frame.occupied[k] % grid.side)),
                                      grid.centre(static_cast<int>(frame.occupied[k] / grid.side)));
    frame.range[k] = frame.centre[k].norm();
  }
  return frame;
}

}  // namespace segmentation_detail
}  // namespace granular
