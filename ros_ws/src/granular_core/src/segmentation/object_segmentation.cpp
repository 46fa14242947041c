#include "granular_core/segmentation/object_segmentation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>

#include "granular_core/geometry/footprint.h"

namespace granular {
namespace {

// m: the min-area rectangle passes through the extreme points, which rounding would put
// outside a box drawn on it.
constexpr double kEdgeAllowance = 0.005;

// A square grid of `side` x `side` cells of edge `size` centred on the sensor; cell
// row * side + col covers x in [-half + col * size, ...), y likewise with row.
struct PlaneGrid {
  double size = 0.0;
  double half = 0.0;
  int side = 0;

  PlaneGrid(double cell_size, double half_extent)
      : size(cell_size),
        half(half_extent),
        side(static_cast<int>(std::ceil(2.0 * half_extent / cell_size - 1e-9))) {}

  std::size_t cells() const { return static_cast<std::size_t>(side) * side; }
  // The cell of (x, y), or nullopt outside the grid.
  std::optional<std::size_t> cellOf(double x, double y) const {
    const double col = std::floor((x + half) / size);
    const double row = std::floor((y + half) / size);
    if (col < 0 || row < 0 || col >= side || row >= side) {
      return std::nullopt;
    }
    return static_cast<std::size_t>(row) * side + static_cast<std::size_t>(col);
  }
  double centre(int index) const { return -half + (index + 0.5) * size; }
};

// Disjoint sets of occupied cells, union by size with path halving.
class Components {
 public:
  explicit Components(std::size_t count) : parent_(count), size_(count, 1) {
    std::iota(parent_.begin(), parent_.end(), 0u);
  }
  std::uint32_t find(std::uint32_t i) {
    while (parent_[i] != i) {
      parent_[i] = parent_[parent_[i]];
      i = parent_[i];
    }
    return i;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) {
      return;
    }
    if (size_[a] < size_[b]) {
      std::swap(a, b);
    }
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<std::uint32_t> parent_;
  std::vector<std::uint32_t> size_;
};

// What the gates look at, for one segment.
struct SegmentShape {
  Rectangle footprint;
  std::size_t points = 0;
  double range = 0.0;         ///< m, of the points' centre
  double top = 0.0;           ///< m above the ground: the highest point
  double bottom = 0.0;        ///< m above the ground: the lowest point
  double column_top = 0.0;    ///< m above the ground: the highest return over its cells
  double normal_tilt_deg = 90.0;  ///< of the least-variance direction of the points
  double thickness = 0.0;     ///< m, the spread along that direction
};

// The size gates on the footprint, or nullptr.
const char* failedSizeGate(const Rectangle& box, const SegmentGates& gates) {
  if (box.length > gates.max_length || box.width > gates.max_width ||
      box.length * box.width > gates.max_area) {
    return "max_size";
  }
  if (box.length > gates.wall_length && box.width < gates.wall_width) {
    return "wall";
  }
  return nullptr;
}

// Spread of the points along their least-variance direction, and that direction's angle from
// vertical.
void principalThickness(const Cloud& cloud, const std::vector<std::size_t>& indices,
                        SegmentShape& shape) {
  if (indices.size() < 3) {
    return;
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const std::size_t i : indices) {
    mean += cloud[i].getVector3fMap().cast<double>();
  }
  mean /= static_cast<double>(indices.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const std::size_t i : indices) {
    const Eigen::Vector3d d = cloud[i].getVector3fMap().cast<double>() - mean;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(indices.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  shape.thickness = std::sqrt(std::max(0.0, solver.eigenvalues()(0)));
  shape.normal_tilt_deg =
      std::acos(std::min(1.0, std::abs(solver.eigenvectors().col(0).z()))) * 180.0 / M_PI;
}

}  // namespace

void validate(const ObjectSegmentationConfig& config) {
  config::validateFields(config);
  config::require(config.min_range < config.max_range, "min_range must be below max_range");
  config::require(2.0 * config.max_range / config.cell_size <= 20000.0,
                  "2 max_range / cell_size must be at most 20000 cells a side");
}

ObjectSegmenter::ObjectSegmenter(const ObjectSegmentationConfig& config) : config_(config) {
  validate(config_);
  slot_.assign(PlaneGrid(config_.cell_size, config_.max_range).cells(), -1);
}

ObjectSegmentation segmentObjects(const Cloud& cloud, const GroundConfig& ground,
                                  const ObjectSegmentationConfig& config) {
  return ObjectSegmenter(config).segment(cloud, estimateGround(cloud, ground));
}

ObjectSegmentation ObjectSegmenter::segment(const Cloud& cloud, GroundEstimate ground) {
  const ObjectSegmentationConfig& config = config_;
  if (ground.heights.size() != cloud.size() || ground.ground.size() != cloud.size()) {
    throw std::invalid_argument("ObjectSegmenter::segment: the ground is not this cloud's");
  }
  ObjectSegmentation result;
  result.ground = std::move(ground);
  const std::vector<float>& heights = result.ground.heights;
  const std::vector<bool>& on_ground = result.ground.ground;

  // Candidates: standing above the ground, below overhangs, off the own vehicle, on the grid;
  // their cells become the frame's occupied cells (slot_ numbers them as they come).
  const PlaneGrid grid(config.cell_size, config.max_range);
  std::vector<std::size_t> candidates;
  std::vector<std::size_t> overhangs;  // higher than candidates, up to 8 m
  std::vector<std::uint32_t> candidate_slot;
  std::vector<std::uint32_t> occupied;  // grid cells, in the order first met
  const double min_range_sq = config.min_range * config.min_range;
  const double max_range_sq = config.max_range * config.max_range;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const float height = heights[i];
    if (on_ground[i] || !std::isfinite(height)) {
      continue;
    }
    const PointXYZIT& point = cloud[i];
    const double range_sq = double(point.x) * point.x + double(point.y) * point.y;
    if (range_sq <= min_range_sq || range_sq >= max_range_sq) {
      continue;
    }
    if (height > config.max_height) {
      if (height < 8.0f) {
        overhangs.push_back(i);
      }
      continue;
    }
    if (const auto cell = grid.cellOf(point.x, point.y)) {
      std::int32_t& slot = slot_[*cell];
      if (slot < 0) {
        slot = static_cast<std::int32_t>(occupied.size());
        occupied.push_back(static_cast<std::uint32_t>(*cell));
      }
      candidates.push_back(i);
      candidate_slot.push_back(static_cast<std::uint32_t>(slot));
    }
  }
  // The highest return over each occupied cell: its candidates' and the overhangs above it.
  std::vector<float> cell_top(occupied.size(), 0.0f);
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    cell_top[candidate_slot[c]] = std::max(cell_top[candidate_slot[c]], heights[candidates[c]]);
  }
  for (const std::size_t i : overhangs) {
    if (const auto cell = grid.cellOf(cloud[i].x, cloud[i].y); cell && slot_[*cell] >= 0) {
      float& top = cell_top[static_cast<std::size_t>(slot_[*cell])];
      top = std::max(top, heights[i]);
    }
  }
  // Occupied cells in row-major order, so that segments come in a fixed order.
  std::sort(occupied.begin(), occupied.end());
  std::vector<std::uint32_t> renumbered(occupied.size());
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    renumbered[static_cast<std::size_t>(slot_[occupied[k]])] = static_cast<std::uint32_t>(k);
    slot_[occupied[k]] = static_cast<std::int32_t>(k);
  }
  // The candidates of each occupied cell (a counting sort over the occupied cells only).
  std::vector<std::uint32_t> start(occupied.size() + 1, 0);
  for (std::uint32_t& slot : candidate_slot) {
    slot = renumbered[slot];
    ++start[slot + 1];
  }
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    start[k + 1] += start[k];
  }
  std::vector<std::size_t> by_cell(candidates.size());
  {
    std::vector<std::uint32_t> next(start.begin(), start.end() - 1);
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      by_cell[next[candidate_slot[c]]++] = candidates[c];
    }
  }

  const double reach_per_m =
      config.link_azimuth_steps * config.azimuth_step_deg * M_PI / 180.0 / config.cell_size;
  std::vector<int> link(occupied.size());
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    const double range = std::hypot(grid.centre(static_cast<int>(occupied[k] % grid.side)),
                                     grid.centre(static_cast<int>(occupied[k] / grid.side)));
    link[k] = std::max(config.link_cells, static_cast<int>(std::ceil(reach_per_m * range)));
  }
  // A pair of cells joins when it lies within the larger of their two reaches. The reach
  // grows by at most one cell over a reach's distance, so scanning the rows and columns after
  // each cell up to its reach plus one finds every pair once.
  Components components(occupied.size());
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    const int row = static_cast<int>(occupied[k] / grid.side);
    const int col = static_cast<int>(occupied[k] % grid.side);
    const int window = link[k] + 1;
    for (int r = row; r <= std::min(row + window, grid.side - 1); ++r) {
      const int first_col = r == row ? col + 1 : std::max(col - window, 0);
      const std::int32_t* cells = slot_.data() + static_cast<std::size_t>(r) * grid.side;
      for (int c = first_col; c <= std::min(col + window, grid.side - 1); ++c) {
        const std::int32_t other = cells[c];
        if (other >= 0 &&
            std::max(r - row, std::abs(c - col)) <= std::max(link[k], link[other])) {
          components.join(static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(other));
        }
      }
    }
  }
  // A cell whose four diagonal neighbours are all occupied holds no corner of its segment's
  // footprint: the cells are half-open, so every point of the cell up and to the right lies
  // strictly above and to the right of each of its points, and likewise for the other three
  // quadrants; no direction has one of its points extreme. The footprint's hull is taken over
  // the other cells' points only (on a near car most cells are inner), with the same result.
  std::vector<bool> inner(occupied.size(), false);
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    const int row = static_cast<int>(occupied[k] / grid.side);
    const int col = static_cast<int>(occupied[k] % grid.side);
    if (row == 0 || col == 0 || row == grid.side - 1 || col == grid.side - 1) {
      continue;
    }
    const auto occupiedAt = [&](int r, int c) {
      return slot_[static_cast<std::size_t>(r) * grid.side + static_cast<std::size_t>(c)] >= 0;
    };
    inner[k] = occupiedAt(row - 1, col - 1) && occupiedAt(row - 1, col + 1) &&
               occupiedAt(row + 1, col - 1) && occupiedAt(row + 1, col + 1);
  }
  for (const std::uint32_t cell : occupied) {
    slot_[cell] = -1;  // empty again for the next frame
  }
  std::vector<float> top_of_cell(occupied.size());
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    top_of_cell[renumbered[k]] = cell_top[k];
  }

  // Each component's points, components in the order of their first cell.
  std::vector<std::int32_t> component_of_root(occupied.size(), -1);
  std::vector<std::vector<std::size_t>> members;
  std::vector<std::vector<std::uint32_t>> outline_cells;  // each component's cells not inner
  std::vector<std::size_t> cell_counts;
  std::vector<double> column_tops;
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    const std::uint32_t root = components.find(static_cast<std::uint32_t>(k));
    if (component_of_root[root] < 0) {
      component_of_root[root] = static_cast<std::int32_t>(members.size());
      members.emplace_back();
      outline_cells.emplace_back();
      cell_counts.push_back(0);
      column_tops.push_back(0.0);
    }
    const auto id = static_cast<std::size_t>(component_of_root[root]);
    ++cell_counts[id];
    column_tops[id] = std::max(column_tops[id], double(top_of_cell[k]));
    members[id].insert(members[id].end(), by_cell.begin() + start[k], by_cell.begin() + start[k + 1]);
    if (!inner[k]) {
      outline_cells[id].push_back(static_cast<std::uint32_t>(k));
    }
  }

  // Each component through the gates, cheapest first: most components are a few stray
  // points, and the footprint's hull and the covariance are only needed for the rest.
  for (std::size_t id = 0; id < members.size(); ++id) {
    std::vector<std::size_t>& indices = members[id];
    const SegmentGates& gates = config.gates;
    const auto reject = [&result](const char* gate) { ++result.rejected[gate]; };
    if (indices.size() < gates.min_points) {
      reject("min_points");
      continue;
    }
    SegmentShape shape;
    shape.points = indices.size();
    double min_z = std::numeric_limits<double>::infinity(), max_z = -min_z;
    shape.top = -std::numeric_limits<double>::infinity();
    shape.bottom = std::numeric_limits<double>::infinity();
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector2d high = -low;
    for (const std::size_t i : indices) {
      min_z = std::min(min_z, double(cloud[i].z));
      max_z = std::max(max_z, double(cloud[i].z));
      shape.top = std::max(shape.top, double(heights[i]));
      shape.bottom = std::min(shape.bottom, double(heights[i]));
      const Eigen::Vector2d xy(cloud[i].x, cloud[i].y);
      mean += xy;
      low = low.cwiseMin(xy);
      high = high.cwiseMax(xy);
    }
    shape.column_top = column_tops[id];
    shape.range = (mean / static_cast<double>(indices.size())).norm();
    if (shape.top < gates.min_top) {
      reject("min_top");
      continue;
    }
    if (shape.bottom > gates.max_bottom + gates.max_bottom_per_m * shape.range) {
      reject("max_bottom");
      continue;
    }
    if (shape.column_top > gates.max_column_top) {
      reject("max_column_top");
      continue;
    }
    // A segment spreading farther along x or y than the diagonal of the largest footprint
    // allowed has a footprint too long or too wide, whatever its rectangle: a building or a
    // row of trees, gated without its hull.
    if ((high - low).maxCoeff() > std::hypot(gates.max_length, gates.max_width)) {
      reject("max_size");
      continue;
    }
    std::vector<Eigen::Vector2d> xy;
    for (const std::uint32_t k : outline_cells[id]) {
      for (std::uint32_t c = start[k]; c < start[k + 1]; ++c) {
        xy.emplace_back(cloud[by_cell[c]].x, cloud[by_cell[c]].y);
      }
    }
    shape.footprint = minimumAreaRectangle(xy);
    const Rectangle& footprint = shape.footprint;
    if (const char* gate = failedSizeGate(footprint, gates)) {
      reject(gate);
      continue;
    }
    if (std::hypot(footprint.length, footprint.width) < gates.pole_diagonal &&
        shape.column_top > gates.pole_top) {
      reject("pole");
      continue;
    }
    principalThickness(cloud, indices, shape);
    if (shape.normal_tilt_deg < gates.terrain_angle_deg &&
        shape.thickness < gates.terrain_thickness) {
      reject("terrain");
      continue;
    }
    std::sort(indices.begin(), indices.end());
    // From the ground under the segment to its highest point; the footprint and the top grown
    // by kEdgeAllowance, so that cropping by the box keeps the points on its faces.
    const double floor = min_z - shape.bottom;
    const double top = max_z + kEdgeAllowance;
    const OrientedBox box(
        Eigen::Vector3d(footprint.centre.x(), footprint.centre.y(), 0.5 * (floor + top)),
        Eigen::Quaterniond(Eigen::AngleAxisd(footprint.yaw, Eigen::Vector3d::UnitZ())),
        Eigen::Vector3d(std::max(footprint.length + 2.0 * kEdgeAllowance, config.cell_size),
                        std::max(footprint.width + 2.0 * kEdgeAllowance, config.cell_size),
                        std::max(top - floor, config.cell_size)));
    result.segments.push_back(Segment{box, std::move(indices), cell_counts[id]});
  }
  return result;
}

void validate(const SegmentationStageConfig& config) {
  validate(config.objects);
  validate(config.occupancy);
  validate(config.background);
}

FrameSegmenter::FrameSegmenter(const GroundConfig& ground, const SegmentationStageConfig& config)
    : ground_(ground), config_(config), objects_(config.objects) {
  validate(ground_);
  validate(config_);
}

ObjectSegmentation FrameSegmenter::segment(const Cloud& cloud) {
  if (config_.method == SegmentationMethod::kObjects) {
    return objects_.segment(cloud, estimateGround(cloud, ground_));
  }
  ObjectSegmentation result;
  result.segments = segmentCloud(cloud, config_.occupancy);
  return result;
}

}  // namespace granular
