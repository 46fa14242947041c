#include "granular_core/segmentation/occupancy_segmentation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

namespace granular {
namespace {

// Bounds the grid's memory (about 5 bytes a cell) to 500 MB.
constexpr double kMaxCellsPerSide = 10000.0;
// Points on the footprint's edge, the corners of the enclosed cells among them, belong to it
// despite rounding.
constexpr double kEdgeTolerance = 1e-6;  // m

constexpr std::uint8_t kEmpty = 0;
constexpr std::uint8_t kOccupied = 1;
constexpr std::uint8_t kLabelled = 2;

// Cell (col, row) is number row * side + col and covers
// [-half + col * cell_size, -half + (col + 1) * cell_size) in x, likewise in y with row.
struct Grid {
  double cell_size = 0.0;
  double half = 0.0;
  int side = 0;

  std::size_t cells() const { return static_cast<std::size_t>(side) * side; }
  double centre(int index) const { return -half + (index + 0.5) * cell_size; }
  // The cell index of coordinate `value`, clamped to the grid.
  int clampedIndex(double value) const {
    const double index = std::floor((value + half) / cell_size);
    return static_cast<int>(std::clamp(index, 0.0, static_cast<double>(side - 1)));
  }
};

// The grid's points sorted by cell (a counting sort): the points of cell c are positions
// begin[c] .. begin[c + 1] - 1 of xyz (coordinates) and index (their index in the cloud), in
// cloud order. Row-major numbering makes the cells of one row's column range one span.
struct PointsByCell {
  std::vector<std::uint32_t> begin;
  std::vector<Eigen::Vector3f> xyz;
  std::vector<std::uint32_t> index;
};

PointsByCell sortByCell(const Cloud& cloud, const Grid& grid) {
  std::vector<std::int32_t> cell_of(cloud.size(), -1);
  PointsByCell sorted;
  // Counts land two places up so that after the prefix sum begin[c + 1] is the start of cell c,
  // and after the scatter, which advances it to the end of c, begin[c] is that start.
  sorted.begin.assign(grid.cells() + 2, 0);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const PointXYZIT& point = cloud[i];
    if (!std::isfinite(point.x) || !std::isfinite(point.y) || !std::isfinite(point.z) ||
        point.x < -grid.half || point.x >= grid.half || point.y < -grid.half ||
        point.y >= grid.half) {
      continue;
    }
    const int cell = grid.clampedIndex(point.y) * grid.side + grid.clampedIndex(point.x);
    cell_of[i] = cell;
    ++sorted.begin[cell + 2];
  }
  for (std::size_t c = 1; c < sorted.begin.size(); ++c) {
    sorted.begin[c] += sorted.begin[c - 1];
  }
  const std::uint32_t kept = sorted.begin.back();
  sorted.xyz.resize(kept);
  sorted.index.resize(kept);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    if (cell_of[i] >= 0) {
      const std::uint32_t position = sorted.begin[cell_of[i] + 1]++;
      sorted.xyz[position] = cloud[i].getVector3fMap();
      sorted.index[position] = static_cast<std::uint32_t>(i);
    }
  }
  return sorted;
}

// kOccupied where max z - min z of the cell's points exceeds the threshold, else kEmpty.
std::vector<std::uint8_t> occupancy(const PointsByCell& sorted, const Grid& grid,
                                    double height_threshold) {
  std::vector<std::uint8_t> state(grid.cells(), kEmpty);
  for (std::size_t c = 0; c < state.size(); ++c) {
    const std::uint32_t first = sorted.begin[c];
    const std::uint32_t end = sorted.begin[c + 1];
    if (end - first < 2) {
      continue;
    }
    float min_z = sorted.xyz[first].z();
    float max_z = min_z;
    for (std::uint32_t k = first + 1; k < end; ++k) {
      min_z = std::min(min_z, sorted.xyz[k].z());
      max_z = std::max(max_z, sorted.xyz[k].z());
    }
    if (static_cast<double>(max_z) - min_z > height_threshold) {
      state[c] = kOccupied;
    }
  }
  return state;
}

// Labels the kOccupied component of `seed` (cells at most `link` rows and columns apart are
// connected; 1 is 8-connectivity) kLabelled and returns its cells in breadth-first order;
// `cells` is reused storage.
void growComponent(std::uint32_t seed, const Grid& grid, int link,
                   std::vector<std::uint8_t>& state, std::vector<std::uint32_t>& cells) {
  cells.clear();
  cells.push_back(seed);
  state[seed] = kLabelled;
  for (std::size_t head = 0; head < cells.size(); ++head) {
    const int row = static_cast<int>(cells[head] / grid.side);
    const int col = static_cast<int>(cells[head] % grid.side);
    for (int r = std::max(row - link, 0); r <= std::min(row + link, grid.side - 1); ++r) {
      for (int c = std::max(col - link, 0); c <= std::min(col + link, grid.side - 1); ++c) {
        const std::uint32_t neighbour = static_cast<std::uint32_t>(r * grid.side + c);
        if (state[neighbour] == kOccupied) {
          state[neighbour] = kLabelled;
          cells.push_back(neighbour);
        }
      }
    }
  }
}

// Heading of the major principal axis of the cells' (col, row) coordinates, in (-pi/2, pi/2].
// The covariance numerators are exact integers (128 bits: n * sum u^2 outgrows 64 for large
// components), so a shape symmetric about the grid axes gets exactly yaw 0 or pi/2 and an
// isotropic one yaw 0 rather than the direction of rounding noise.
double principalYaw(const std::vector<std::uint32_t>& cells, const Grid& grid) {
  __int128 n = 0, su = 0, sv = 0, suu = 0, svv = 0, suv = 0;
  for (const std::uint32_t cell : cells) {
    const __int128 u = cell % grid.side;
    const __int128 v = cell / grid.side;
    ++n;
    su += u;
    sv += v;
    suu += u * u;
    svv += v * v;
    suv += u * v;
  }
  const auto uu = static_cast<double>(n * suu - su * su);
  const auto vv = static_cast<double>(n * svv - sv * sv);
  const auto uv = static_cast<double>(n * suv - su * sv);
  return 0.5 * std::atan2(2.0 * uv, uu - vv);
}

std::optional<Segment> segmentOf(const std::vector<std::uint32_t>& cells,
                                 const PointsByCell& sorted, const Grid& grid,
                                 const SegmentationConfig& config) {
  const double yaw = principalYaw(cells, grid);
  const double cos_yaw = std::cos(yaw);
  const double sin_yaw = std::sin(yaw);

  // Extremes of the cell centres along the axes (u along e1, v along e2), widened so that the
  // footprint encloses the whole cells, which also puts every point of the cells inside it.
  double min_u = std::numeric_limits<double>::infinity();
  double max_u = -min_u, min_v = min_u, max_v = -min_u;
  for (const std::uint32_t cell : cells) {
    const double x = grid.centre(static_cast<int>(cell % grid.side));
    const double y = grid.centre(static_cast<int>(cell / grid.side));
    const double u = x * cos_yaw + y * sin_yaw;
    const double v = -x * sin_yaw + y * cos_yaw;
    min_u = std::min(min_u, u);
    max_u = std::max(max_u, u);
    min_v = std::min(min_v, v);
    max_v = std::max(max_v, v);
  }
  const double margin = 0.5 * grid.cell_size * (std::abs(cos_yaw) + std::abs(sin_yaw));
  const double half_length = 0.5 * (max_u - min_u) + margin;
  const double half_width = 0.5 * (max_v - min_v) + margin;
  if (2.0 * std::max(half_length, half_width) > config.max_length) {
    return std::nullopt;
  }
  // The middle of the extremes, not the paper's centre of gravity: a box around the centre of
  // gravity that encloses the cells would be larger than the cells' extent where they lie
  // unevenly (one side of a car seen).
  const double mid_u = 0.5 * (min_u + max_u);
  const double mid_v = 0.5 * (min_v + max_v);
  const double centre_x = mid_u * cos_yaw - mid_v * sin_yaw;
  const double centre_y = mid_u * sin_yaw + mid_v * cos_yaw;

  // The paper's polygon query, over the cells under the footprint's axis-aligned bounding box,
  // each point tested against the footprint.
  const double reach_x = half_length * std::abs(cos_yaw) + half_width * std::abs(sin_yaw);
  const double reach_y = half_length * std::abs(sin_yaw) + half_width * std::abs(cos_yaw);
  const int first_col = grid.clampedIndex(centre_x - reach_x);
  const int last_col = grid.clampedIndex(centre_x + reach_x);
  const int first_row = grid.clampedIndex(centre_y - reach_y);
  const int last_row = grid.clampedIndex(centre_y + reach_y);
  std::vector<std::size_t> indices;
  float min_z = std::numeric_limits<float>::infinity();
  float max_z = -min_z;
  for (int row = first_row; row <= last_row; ++row) {
    const std::size_t row_start = static_cast<std::size_t>(row) * grid.side;
    const std::uint32_t end = sorted.begin[row_start + last_col + 1];
    for (std::uint32_t k = sorted.begin[row_start + first_col]; k < end; ++k) {
      const Eigen::Vector3f& point = sorted.xyz[k];
      const double dx = point.x() - centre_x;
      const double dy = point.y() - centre_y;
      if (std::abs(dx * cos_yaw + dy * sin_yaw) <= half_length + kEdgeTolerance &&
          std::abs(-dx * sin_yaw + dy * cos_yaw) <= half_width + kEdgeTolerance) {
        indices.push_back(sorted.index[k]);
        min_z = std::min(min_z, point.z());
        max_z = std::max(max_z, point.z());
      }
    }
  }
  if (indices.empty() || indices.size() < config.min_points) {
    return std::nullopt;
  }
  std::sort(indices.begin(), indices.end());

  const double height = std::max(static_cast<double>(max_z) - min_z, grid.cell_size);
  const OrientedBox box(
      Eigen::Vector3d(centre_x, centre_y, 0.5 * (static_cast<double>(min_z) + max_z)),
      Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())),
      Eigen::Vector3d(2.0 * half_length, 2.0 * half_width, height));
  return Segment{box, std::move(indices), cells.size()};
}

}  // namespace

void validate(const SegmentationConfig& config) {
  config::validateFields(config);
  config::require(config.extent / config.cell_size <= kMaxCellsPerSide,
          "extent / cell_size must be at most 10000 cells a side");
}

std::vector<Segment> segmentCloud(const Cloud& cloud, const SegmentationConfig& config) {
  validate(config);
  if (cloud.size() > std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument("segmentCloud: more than 2^32 - 1 points");
  }
  Grid grid;
  grid.cell_size = config.cell_size;
  grid.half = 0.5 * config.extent;
  // The tolerance keeps an extent that is a multiple of cell_size from gaining a sliver column.
  grid.side = static_cast<int>(std::ceil(config.extent / config.cell_size - 1e-9));

  const PointsByCell sorted = sortByCell(cloud, grid);
  std::vector<std::uint8_t> state = occupancy(sorted, grid, config.height_threshold);

  std::vector<Segment> segments;
  std::vector<std::uint32_t> cells;
  for (std::uint32_t seed = 0; seed < state.size(); ++seed) {
    if (state[seed] != kOccupied) {
      continue;
    }
    growComponent(seed, grid, config.link_cells, state, cells);
    if (cells.size() < config.min_cells) {
      continue;
    }
    if (std::optional<Segment> segment = segmentOf(cells, sorted, grid, config)) {
      segments.push_back(std::move(*segment));
    }
  }
  return segments;
}

SegmentationMatch matchSegments(const std::vector<OrientedBox>& segments,
                                const std::vector<OrientedBox>& truth, double max_distance) {
  config::require(std::isfinite(max_distance) && max_distance >= 0.0,
          "max_distance must be a finite number, not negative");
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;  // distance, truth, segment
  for (std::size_t t = 0; t < truth.size(); ++t) {
    for (std::size_t s = 0; s < segments.size(); ++s) {
      const double distance =
          (truth[t].centre().head<2>() - segments[s].centre().head<2>()).norm();
      if (distance <= max_distance) {
        pairs.emplace_back(distance, t, s);
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> truth_used(truth.size(), false);
  std::vector<bool> segment_used(segments.size(), false);
  SegmentationMatch match;
  match.truth = truth.size();
  match.segments = segments.size();
  for (const auto& [distance, t, s] : pairs) {
    if (!truth_used[t] && !segment_used[s]) {
      truth_used[t] = true;
      segment_used[s] = true;
      ++match.matched_truth;
    }
  }
  match.unmatched_segments = match.segments - match.matched_truth;
  return match;
}

}  // namespace granular
