// ObjectSegmenter: candidates on a range-aware grid (buildFrameGrid, segment_grid.h), cells
// linked into components (joinNeighbours over a LinkCells view), the gates (gateSegment over a
// FrameCells view, its verdict a Rejection) and the walls peeled off what they reject
// (peelWall). (Over 400 lines: the links, the gates and the walls read one frame's cell tables
// through views that stay private to this file.)
#include "granular_core/segmentation/object_segmentation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <utility>

#include <Eigen/Eigenvalues>

#include "granular_core/geometry/footprint.h"
#include "segment_grid.h"

namespace granular {
namespace {

using segmentation_detail::CellBits;
using segmentation_detail::FrameGrid;
using segmentation_detail::PlaneGrid;

// m: the min-area rectangle passes through the extreme points, which rounding would put
// outside a box drawn on it.
constexpr double kEdgeAllowance = 0.005;

// Cells that vote in a wall's Hough search (WallPeeling), at most.
constexpr std::size_t kHoughCells = 400;

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

// The places 0 .. count - 1 grouped by their component (ascending within each), the groups in
// the order of their first place.
std::vector<std::vector<std::uint32_t>> groupsOf(Components& components, std::size_t count) {
  std::vector<std::int32_t> group_of_root(count, -1);
  std::vector<std::vector<std::uint32_t>> groups;
  for (std::uint32_t place = 0; place < count; ++place) {
    const std::uint32_t root = components.find(place);
    if (group_of_root[root] < 0) {
      group_of_root[root] = static_cast<std::int32_t>(groups.size());
      groups.emplace_back();
    }
    groups[static_cast<std::size_t>(group_of_root[root])].push_back(place);
  }
  return groups;
}

// Per cell of a segment (`cells`, places in `occupied`, whose grid cells lie in rows
// least_row .. most_row of a grid `side` cells wide), whether it is enclosed: the segment has
// cells in all four open quadrants around it (up and right, up and left, down and right, down
// and left). The cells are half-open, so every point of a cell up and to the right lies
// strictly above and to the right of each point of this one, and likewise for the others: in
// every direction some point of the segment lies strictly farther than any of this cell's,
// none of which can be a corner of the footprint's hull, which the other cells' points give
// alone, the same. On a bush or a near car most cells are enclosed.
std::vector<bool> enclosedCells(const std::vector<std::uint32_t>& cells,
                                const std::vector<std::uint32_t>& occupied, int side,
                                int least_row, int most_row) {
  const auto rows = static_cast<std::size_t>(most_row - least_row + 1);
  // Per row (from least_row): its cells' least and most column, then the least and most
  // column of the rows above it and of the rows below it.
  std::vector<int> row_least(rows, side), row_most(rows, -1);
  for (const std::uint32_t k : cells) {
    const std::size_t row = occupied[k] / static_cast<std::uint32_t>(side) - least_row;
    const int col = static_cast<int>(occupied[k] % static_cast<std::uint32_t>(side));
    row_least[row] = std::min(row_least[row], col);
    row_most[row] = std::max(row_most[row], col);
  }
  std::vector<int> above_least(rows, side), above_most(rows, -1);
  for (std::size_t row = rows - 1; row-- > 0;) {
    above_least[row] = std::min(above_least[row + 1], row_least[row + 1]);
    above_most[row] = std::max(above_most[row + 1], row_most[row + 1]);
  }
  std::vector<int> below_least(rows, side), below_most(rows, -1);
  for (std::size_t row = 1; row < rows; ++row) {
    below_least[row] = std::min(below_least[row - 1], row_least[row - 1]);
    below_most[row] = std::max(below_most[row - 1], row_most[row - 1]);
  }
  std::vector<bool> enclosed(cells.size());
  for (std::size_t j = 0; j < cells.size(); ++j) {
    const std::size_t row = occupied[cells[j]] / static_cast<std::uint32_t>(side) - least_row;
    const int col = static_cast<int>(occupied[cells[j]] % static_cast<std::uint32_t>(side));
    enclosed[j] = above_least[row] < col && above_most[row] > col && below_least[row] < col &&
                  below_most[row] > col;
  }
  return enclosed;
}

// Why a segment is removed: the first gate it fails, or a wall peeled off it. The names are
// the keys of ObjectSegmentation::rejected.
enum class Rejection {
  kMinPoints,
  kMaxSize,
  kMinTop,
  kMaxBottom,
  kMaxColumnTop,
  kWall,
  kPole,
  kTerrain,
  kWallsPeeled,
};

const char* rejectionName(Rejection rejection) {
  switch (rejection) {
    case Rejection::kMinPoints:
      return "min_points";
    case Rejection::kMaxSize:
      return "max_size";
    case Rejection::kMinTop:
      return "min_top";
    case Rejection::kMaxBottom:
      return "max_bottom";
    case Rejection::kMaxColumnTop:
      return "max_column_top";
    case Rejection::kWall:
      return "wall";
    case Rejection::kPole:
      return "pole";
    case Rejection::kTerrain:
      return "terrain";
    case Rejection::kWallsPeeled:
      return "walls_peeled";
  }
  return "";
}

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

// Whether the footprint is larger than any vehicle's.
bool tooLarge(const Rectangle& box, const SegmentGates& gates) {
  return box.length > gates.max_length || box.width > gates.max_width ||
         box.length * box.width > gates.max_area;
}

// Whether the footprint is as long and thin as a wall's (isVehicleSide may still keep it).
bool wallShaped(const Rectangle& box, const SegmentGates& gates) {
  return box.length > gates.wall_length && box.width < gates.wall_width;
}

// The wall gate's exception: a long thin segment whose lowest point, piece by piece along
// it, stands clear of the ground over most of its length (the body between a bus's wheels; a
// wall, fence or hedge reaches the ground, up to the gap between scan rings, which grows with
// range as max_bottom's allowance does) and whose top is high (a guard rail's is not).
bool isVehicleSide(const Cloud& cloud, const std::vector<std::size_t>& indices,
                   const std::vector<float>& heights, const SegmentShape& shape,
                   const SegmentGates& gates) {
  if (shape.top <= gates.side_top) {
    return false;
  }
  const Rectangle& footprint = shape.footprint;
  const Eigen::Vector2d axis(std::cos(footprint.yaw), std::sin(footprint.yaw));
  const auto pieces = static_cast<std::size_t>(footprint.length / gates.side_bin) + 1;
  std::vector<float> lowest(pieces, std::numeric_limits<float>::infinity());
  for (const std::size_t i : indices) {
    const double along =
        (Eigen::Vector2d(cloud[i].x, cloud[i].y) - footprint.centre).dot(axis) +
        0.5 * footprint.length;
    const auto piece = static_cast<std::size_t>(
        std::clamp(along / gates.side_bin, 0.0, static_cast<double>(pieces - 1)));
    lowest[piece] = std::min(lowest[piece], heights[i]);
  }
  const double clearance = gates.side_clearance + gates.max_bottom_per_m * shape.range;
  std::size_t seen = 0, clear = 0;
  for (const float low : lowest) {
    seen += std::isfinite(low);
    clear += std::isfinite(low) && low > clearance;
  }
  return seen > 0 && static_cast<double>(clear) >= gates.side_share * static_cast<double>(seen);
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

// One frame's occupied cells as the links and the walls read them: cell k's grid cell
// (occupied[k]), centre, range, reach in cells (link[k]) and whether it is low; `slot` and
// `held` map a grid cell to its place among the cells being linked (slot -1 and no bit
// elsewhere).
struct LinkCells {
  const ObjectSegmentationConfig& config;
  const PlaneGrid& grid;
  const std::vector<std::uint32_t>& occupied;
  const std::vector<Eigen::Vector2d>& centre;
  const std::vector<double>& range;
  const std::vector<int>& link;
  const std::vector<std::uint8_t>& low;
  double reach_per_m;   ///< cells of reach per metre of range
  double across_per_m;  ///< link_azimuth_steps returns' spacing per metre of range
  std::vector<std::int32_t>& slot;
  CellBits& held;
};

// Cells farther apart than link_cells join only when close across the line of sight: the
// nearer one's offset from the ray to the farther one (|a x b| / |b|) at most
// link_azimuth_steps returns' spacing at the farther one's range, and one cell for where in
// their cells the points lie.
bool closeAcross(const LinkCells& frame, std::uint32_t a, std::uint32_t b) {
  const std::vector<double>& range = frame.range;
  const std::vector<Eigen::Vector2d>& centre = frame.centre;
  const double farther = std::max(range[a], range[b]);
  const double cross = std::abs(centre[a].x() * centre[b].y() - centre[a].y() * centre[b].x());
  return cross <= (frame.across_per_m * farther + frame.config.cell_size) * farther;
}

// A pair of cells joins when it lies within the larger of their two reaches (and, beyond
// link_cells, close across the line of sight). The reach grows by at most one cell over a
// reach's distance, so scanning the rows and columns after each cell up to the longest reach
// of a cell within its own reach plus one finds every pair once: its reach plus one only
// where that crosses a step of the reach (beyond link_cells), its own reach elsewhere.
// A low cell (a kerb, a verge, the foot of a hedge, a car's underside) never links two
// taller ones: it joins only the nearest cell that is not low among those it would join (the
// first scanned on a tie), after those have joined each other; low cells with no such
// neighbour join each other (a kerb stays one piece).
// `cells` are occupied cells (k) whose slot holds their place in `cells` (and whose bit is
// set: only theirs); `components` joins places.
void joinNeighbours(const LinkCells& frame, const std::vector<std::uint32_t>& cells,
                    Components& components) {
  const ObjectSegmentationConfig& config = frame.config;
  const PlaneGrid& grid = frame.grid;
  const std::vector<std::uint32_t>& occupied = frame.occupied;
  const std::vector<double>& range = frame.range;
  const std::vector<int>& link = frame.link;
  const std::vector<std::uint8_t>& low = frame.low;
  const double reach_per_m = frame.reach_per_m;
  CellBits& held = frame.held;
  std::vector<std::int32_t> attach(cells.size(), -1);  // the place a low cell joins
  std::vector<int> attach_apart(cells.size(), std::numeric_limits<int>::max());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> low_pairs;
  const auto offer = [&](std::size_t low_place, std::int32_t place, int apart) {
    if (apart < attach_apart[low_place]) {
      attach_apart[low_place] = apart;
      attach[low_place] = place;
    }
  };
  // Held in locals: the joins write memory the compiler cannot tell apart from the config's.
  const int side = grid.side;
  const int link_cells = config.link_cells;
  const std::int32_t* const slot = frame.slot.data();
  for (std::size_t j = 0; j < cells.size(); ++j) {
    const std::uint32_t k = cells[j];
    const int row = static_cast<int>(occupied[k] / side);
    const int col = static_cast<int>(occupied[k] % side);
    const bool k_low = low[k] != 0;
    // A cell l scanned from here lies at most (link[k] + 1) cells' diagonals farther away.
    const double farthest = range[k] + (link[k] + 1) * config.cell_size * M_SQRT2 + 1e-6;
    const int window =
        std::max(link_cells, static_cast<int>(std::ceil(reach_per_m * farthest)));
    const int last_col = std::min(col + window, side - 1);
    for (int r = row; r <= std::min(row + window, side - 1); ++r) {
      const int first_col = r == row ? col + 1 : std::max(col - window, 0);
      const std::int32_t* slots = slot + static_cast<std::size_t>(r) * side;
      held.forEachSet(r, first_col, last_col, [&](int c) {
        const std::int32_t other = slots[c];
        const std::uint32_t l = cells[static_cast<std::size_t>(other)];
        const int apart = std::max(r - row, std::abs(c - col));
        if (apart <= link_cells ||
            (apart <= std::max(link[k], link[l]) && closeAcross(frame, k, l))) {
          if (!k_low && !low[l]) {
            components.join(static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(other));
          } else if (!low[l]) {
            offer(j, other, apart);
          } else if (!k_low) {
            offer(static_cast<std::size_t>(other), static_cast<std::int32_t>(j), apart);
          } else {
            low_pairs.emplace_back(static_cast<std::uint32_t>(j),
                                   static_cast<std::uint32_t>(other));
          }
        }
      });
    }
  }
  for (std::size_t j = 0; j < cells.size(); ++j) {
    if (attach[j] >= 0) {
      components.join(static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(attach[j]));
    }
  }
  for (const auto& [a, b] : low_pairs) {
    if (attach[a] < 0 && attach[b] < 0) {
      components.join(a, b);
    }
  }
}

// The cells left when the longest straight wall (WallPeeling) is taken from `cells`, in the
// pieces they fall into (each ascending, in the order of its first cell), and the wall's
// direction (rad); nullopt when the cells hold no wall.
struct PeeledWall {
  double direction = 0.0;
  std::vector<std::vector<std::uint32_t>> pieces;
};

std::optional<PeeledWall> peelWall(const LinkCells& frame, const std::vector<std::uint32_t>& cells) {
  const ObjectSegmentationConfig& config = frame.config;
  const WallPeeling& walls = config.walls;
  const std::vector<std::uint32_t>& occupied = frame.occupied;
  const std::vector<Eigen::Vector2d>& centre = frame.centre;
  const std::vector<int>& link = frame.link;
  const std::vector<std::uint8_t>& low = frame.low;
  CellBits& held = frame.held;
  std::vector<Eigen::Vector2d> centres;
  centres.reserve(cells.size());
  for (const std::uint32_t k : cells) {
    centres.push_back(centre[k]);
  }
  // Hough: the direction and the band of `thickness` across it holding the most cells, over
  // at most kHoughCells of them (evenly strided: a building's facade has thousands), at four
  // times angle_step_deg, then at angle_step_deg around the best.
  const std::size_t stride = (cells.size() + kHoughCells - 1) / kHoughCells;
  std::vector<Eigen::Vector2d> voters;
  for (std::size_t j = 0; j < centres.size(); j += stride) {
    voters.push_back(centres[j]);
  }
  std::size_t best_count = 0;
  double best_angle = 0.0, best_low = 0.0;
  std::vector<double> across(voters.size());
  std::vector<std::uint32_t> counts;
  const auto vote = [&](double angle) {
    const Eigen::Vector2d normal(std::cos(angle * M_PI / 180.0), std::sin(angle * M_PI / 180.0));
    double least = std::numeric_limits<double>::infinity(), most = -least;
    for (std::size_t j = 0; j < voters.size(); ++j) {
      across[j] = normal.dot(voters[j]);
      least = std::min(least, across[j]);
      most = std::max(most, across[j]);
    }
    // Bins of half the thickness, counted two by two: a band straddling a bin's edge
    // counts whole.
    const double bin = walls.thickness / 2;
    counts.assign(static_cast<std::size_t>((most - least) / bin) + 2, 0);
    for (const double distance : across) {
      ++counts[static_cast<std::size_t>((distance - least) / bin)];
    }
    for (std::size_t b = 0; b + 1 < counts.size(); ++b) {
      if (counts[b] + counts[b + 1] > best_count) {
        best_count = counts[b] + counts[b + 1];
        best_angle = angle;
        best_low = least + bin * static_cast<double>(b);
      }
    }
  };
  const double coarse = 4.0 * walls.angle_step_deg;
  for (double angle = 0.0; angle < 180.0; angle += coarse) {
    vote(angle);
  }
  const double around = best_angle;
  for (double angle = around - coarse + walls.angle_step_deg; angle < around + coarse;
       angle += walls.angle_step_deg) {
    vote(angle);
  }
  // The band re-centred on its cells, and its longest run along the wall whose gaps the
  // cells' links bridge. A straight wall's cells lie up to half a cell's diagonal off its
  // line (more when it runs diagonally across the grid).
  const Eigen::Vector2d normal(std::cos(best_angle * M_PI / 180.0),
                               std::sin(best_angle * M_PI / 180.0));
  const Eigen::Vector2d along(-normal.y(), normal.x());
  double line = 0.0;
  std::size_t in_band = 0;
  for (const Eigen::Vector2d& c : centres) {
    const double distance = normal.dot(c);
    if (distance >= best_low && distance < best_low + walls.thickness) {
      line += distance;
      ++in_band;
    }
  }
  line /= static_cast<double>(std::max<std::size_t>(in_band, 1));
  const double half_band = walls.thickness / 2 + config.cell_size * M_SQRT1_2;
  std::vector<double> off_line(cells.size());
  std::vector<std::pair<double, std::size_t>> band;  // (along, place in cells)
  for (std::size_t j = 0; j < cells.size(); ++j) {
    off_line[j] = std::abs(normal.dot(centres[j]) - line);
    if (off_line[j] <= half_band) {
      band.emplace_back(along.dot(centres[j]), j);
    }
  }
  std::sort(band.begin(), band.end());
  const auto gapAt = [&](std::size_t b) {
    return (std::max(link[cells[band[b].second]], link[cells[band[b - 1].second]]) + 1) *
           config.cell_size;
  };
  std::size_t run_first = 0, run_last = 0, first = 0;
  for (std::size_t b = 1; b <= band.size(); ++b) {
    if (b == band.size() || band[b].first - band[b - 1].first > gapAt(b)) {
      if (band[b - 1].first - band[first].first >
          band[run_last].first - band[run_first].first) {
        run_first = first;
        run_last = b - 1;
      }
      first = b;
    }
  }
  // A wall with something beside it: the run is much of the segment's standing cells (low
  // ones, the verge at its foot, join whatever is nearest). Where it is not, the segment is a
  // building or a row of trees, which holds no object to recover.
  if (band.empty() || band[run_last].first - band[run_first].first < config.gates.wall_length) {
    return std::nullopt;
  }
  const auto standing = [&](std::uint32_t k) { return !low[k]; };
  const auto standing_in_run = std::count_if(
      band.begin() + run_first, band.begin() + run_last + 1,
      [&](const std::pair<double, std::size_t>& entry) { return standing(cells[entry.second]); });
  const auto standing_in_segment = std::count_if(cells.begin(), cells.end(), standing);
  if (static_cast<double>(standing_in_run) <
      walls.min_share * static_cast<double>(standing_in_segment)) {
    return std::nullopt;
  }
  std::vector<bool> in_wall(cells.size(), false);
  for (std::size_t b = run_first; b <= run_last; ++b) {
    in_wall[band[b].second] = true;
  }
  std::vector<std::uint32_t> left;
  std::vector<std::size_t> left_place;
  for (std::size_t j = 0; j < cells.size(); ++j) {
    if (!in_wall[j]) {
      left.push_back(cells[j]);
      left_place.push_back(j);
    }
  }
  for (std::size_t j = 0; j < left.size(); ++j) {
    frame.slot[occupied[left[j]]] = static_cast<std::int32_t>(j);
    held.set(occupied[left[j]]);
  }
  Components joined(left.size());
  joinNeighbours(frame, left, joined);
  for (const std::uint32_t k : left) {
    frame.slot[occupied[k]] = -1;
    held.clear(occupied[k]);
  }
  // Slivers of the wall itself (its far face, a rough hedge's fringe: every cell within the
  // wall's thickness of the band, along the run) are no objects.
  const double run_from = band[run_first].first, run_to = band[run_last].first;
  const auto besideWall = [&](std::size_t place) {
    const double at = along.dot(centres[place]);
    return off_line[place] <= half_band + walls.thickness && at >= run_from - config.cell_size &&
           at <= run_to + config.cell_size;
  };
  PeeledWall peeled;
  peeled.direction = std::atan2(along.y(), along.x());
  for (std::vector<std::uint32_t>& piece : groupsOf(joined, left.size())) {
    if (!std::all_of(piece.begin(), piece.end(),
                     [&](std::uint32_t j) { return besideWall(left_place[j]); })) {
      for (std::uint32_t& cell : piece) {
        cell = left[cell];
      }
      peeled.pieces.push_back(std::move(piece));
    }
  }
  return peeled;
}

// What the gates read of one frame's occupied cells: the candidates of cell k (the grid cell
// occupied[k], on a grid `side` cells wide) are by_cell[start[k] .. start[k + 1]), and the
// highest return over it top_of_cell[k].
struct FrameCells {
  const Cloud& cloud;
  const std::vector<float>& heights;
  double sensor_height;  // m above the ground
  int side;
  const std::vector<std::uint32_t>& occupied;
  const std::vector<std::uint32_t>& start;
  const std::vector<std::size_t>& by_cell;
  const std::vector<float>& top_of_cell;
};

// Whether the line of sight from the sensor to `centre` (x, y) at `height` m above the ground
// passes within `margin` over the top of an occupied cell nearer than it by a metre or more:
// then the sensor could not have seen what stands under it there.
bool footHidden(const FrameCells& frame, const Eigen::Vector2d& centre, double height,
                const ObjectSegmentationConfig& config, double margin) {
  const PlaneGrid grid(config.cell_size, config.max_range);
  const Eigen::Vector2d& to = centre;
  const double range = to.norm();
  const Eigen::Vector2d direction = to / range;
  for (double r = config.min_range; r < range - 1.0; r += config.cell_size) {
    const Eigen::Vector2d at = direction * r;
    const std::optional<std::size_t> cell = grid.cellOf(at.x(), at.y());
    if (!cell) {
      continue;
    }
    const auto found =
        std::lower_bound(frame.occupied.begin(), frame.occupied.end(), *cell);
    if (found == frame.occupied.end() || *found != *cell) {
      continue;
    }
    const double sight = frame.sensor_height + (height - frame.sensor_height) * r / range;
    if (frame.top_of_cell[static_cast<std::size_t>(found - frame.occupied.begin())] >=
        sight - margin) {
      return true;
    }
  }
  return false;
}

// The segment of `cells` (ascending) through the gates, cheapest first: most components are a
// few stray points, and the footprint's hull and the covariance are only needed for the rest.
// A segment that passes is added to `segments`; otherwise the first gate it fails is returned.
// `wall_direction` (rad): for a piece left by a peeled wall, the wall's, along which a thin
// piece is more of the wall.
std::optional<Rejection> gateSegment(const FrameCells& frame,
                                     const std::vector<std::uint32_t>& cells,
                                     std::optional<double> wall_direction,
                                     const ObjectSegmentationConfig& config,
                                     std::vector<Segment>& segments) {
  const Cloud& cloud = frame.cloud;
  const std::vector<float>& heights = frame.heights;
  const std::vector<std::uint32_t>& occupied = frame.occupied;
  const std::vector<std::uint32_t>& start = frame.start;
  const std::vector<std::size_t>& by_cell = frame.by_cell;
  const std::vector<float>& top_of_cell = frame.top_of_cell;
  const SegmentGates& gates = config.gates;
  const double max_spread = std::hypot(gates.max_length, gates.max_width);
  std::size_t points = 0;
  int least_row = frame.side, most_row = -1, least_col = frame.side, most_col = -1;
  for (const std::uint32_t k : cells) {
    points += start[k + 1] - start[k];
    const int row = static_cast<int>(occupied[k] / frame.side);
    const int col = static_cast<int>(occupied[k] % frame.side);
    least_row = std::min(least_row, row);
    most_row = std::max(most_row, row);
    least_col = std::min(least_col, col);
    most_col = std::max(most_col, col);
  }
  if (points < gates.min_points) {
    return Rejection::kMinPoints;
  }
  // Cells spread over more than the largest footprint's diagonal, even between their
  // nearest sides: too long or too wide whatever the points (the spread test below, early).
  if ((std::max(most_row - least_row, most_col - least_col) - 1) * config.cell_size >
      max_spread) {
    return Rejection::kMaxSize;
  }
  std::vector<std::size_t> indices;
  indices.reserve(points);
  SegmentShape shape;
  shape.points = points;
  for (const std::uint32_t k : cells) {
    indices.insert(indices.end(), by_cell.begin() + start[k], by_cell.begin() + start[k + 1]);
    shape.column_top = std::max(shape.column_top, double(top_of_cell[k]));
  }
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
  mean /= static_cast<double>(indices.size());
  shape.range = mean.norm();
  if (shape.top < gates.min_top) {
    return Rejection::kMinTop;
  }
  if (shape.bottom > gates.max_bottom + gates.max_bottom_per_m * shape.range &&
      (shape.bottom > gates.max_hidden_bottom || shape.top > gates.max_hidden_top ||
       !footHidden(frame, mean, shape.bottom, config, gates.hidden_foot_margin))) {
    return Rejection::kMaxBottom;
  }
  if (shape.column_top > gates.max_column_top) {
    return Rejection::kMaxColumnTop;
  }
  // A segment spreading farther along x or y than the diagonal of the largest footprint
  // allowed has a footprint too long or too wide, whatever its rectangle: a building or a
  // row of trees, gated without its hull.
  if ((high - low).maxCoeff() > max_spread) {
    return Rejection::kMaxSize;
  }
  const std::vector<bool> enclosed =
      enclosedCells(cells, occupied, frame.side, least_row, most_row);
  std::vector<Eigen::Vector2d> xy;
  for (std::size_t j = 0; j < cells.size(); ++j) {
    if (enclosed[j]) {
      continue;
    }
    const std::uint32_t k = cells[j];
    for (std::uint32_t c = start[k]; c < start[k + 1]; ++c) {
      xy.emplace_back(cloud[by_cell[c]].x, cloud[by_cell[c]].y);
    }
  }
  shape.footprint = minimumAreaRectangle(xy);
  const Rectangle& footprint = shape.footprint;
  if (tooLarge(footprint, gates)) {
    return Rejection::kMaxSize;
  }
  if (wallShaped(footprint, gates) && !isVehicleSide(cloud, indices, heights, shape, gates)) {
    return Rejection::kWall;
  }
  if (wall_direction && footprint.width < gates.wall_width &&
      std::abs(std::remainder(footprint.yaw - *wall_direction, M_PI)) <=
          config.walls.parallel_deg * M_PI / 180.0) {
    return Rejection::kWall;
  }
  if (std::hypot(footprint.length, footprint.width) < gates.pole_diagonal &&
      shape.column_top > gates.pole_top) {
    return Rejection::kPole;
  }
  principalThickness(cloud, indices, shape);
  if (shape.normal_tilt_deg < gates.terrain_angle_deg &&
      shape.thickness < gates.terrain_thickness) {
    return Rejection::kTerrain;
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
  segments.push_back(Segment{box, std::move(indices), cells.size()});
  return std::nullopt;
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

  // Candidates on the grid (buildFrameGrid), each occupied cell's place in slot_.
  const PlaneGrid grid(config.cell_size, config.max_range);
  CellBits held(held_, grid.side);
  const FrameGrid on_grid = buildFrameGrid(cloud, result.ground, config, grid, slot_, held);
  const std::vector<std::uint32_t>& occupied = on_grid.occupied;

  const double step_rad = config.azimuth_step_deg * M_PI / 180.0;
  const double reach_per_m = config.link_range_steps * step_rad / config.cell_size;
  std::vector<int> link(occupied.size());
  for (std::size_t k = 0; k < occupied.size(); ++k) {
    link[k] =
        std::max(config.link_cells, static_cast<int>(std::ceil(reach_per_m * on_grid.range[k])));
  }
  // The links and the walls read the frame's cells through this view (joinNeighbours,
  // peelWall).
  const LinkCells links{config, grid, occupied, on_grid.centre, on_grid.range, link,
                        on_grid.low, reach_per_m, config.link_azimuth_steps * step_rad, slot_,
                        held};
  std::vector<std::uint32_t> all_cells(occupied.size());
  std::iota(all_cells.begin(), all_cells.end(), 0u);
  Components components(occupied.size());
  joinNeighbours(links, all_cells, components);
  for (const std::uint32_t cell : occupied) {
    slot_[cell] = -1;  // empty again for the next frame
    held.clear(cell);
  }

  // Each component's cells (places in all_cells are the cells), in the order of their first.
  const std::vector<std::vector<std::uint32_t>> component_cells =
      groupsOf(components, occupied.size());

  // The gates read the frame's cells through this view (gateSegment).
  const FrameCells frame{cloud,
                         heights,
                         result.ground.plane.heightOf(Eigen::Vector3d::Zero()),
                         grid.side,
                         occupied,
                         on_grid.start,
                         on_grid.by_cell,
                         on_grid.top_of_cell};

  const WallPeeling& walls = config.walls;
  // Each component, and what a wall peeled from it leaves, through the gates.
  const auto gateOrPeel = [&](const auto& self, const std::vector<std::uint32_t>& cells,
                              std::optional<double> wall_direction, int peeled) -> void {
    const std::optional<Rejection> failed =
        gateSegment(frame, cells, wall_direction, config, result.segments);
    if (!failed) {
      return;
    }
    ++result.rejected[rejectionName(*failed)];
    if (peeled < walls.max_walls && cells.size() <= walls.max_cells &&
        (*failed == Rejection::kMaxSize || *failed == Rejection::kWall)) {
      if (const std::optional<PeeledWall> wall = peelWall(links, cells)) {
        ++result.rejected[rejectionName(Rejection::kWallsPeeled)];
        for (const std::vector<std::uint32_t>& piece : wall->pieces) {
          self(self, piece, wall->direction, peeled + 1);
        }
      }
    }
  };
  for (const std::vector<std::uint32_t>& cells : component_cells) {
    gateOrPeel(gateOrPeel, cells, std::nullopt, 0);
  }
  return result;
}

void validate(const SegmentationStageConfig& config) {
  // Every field, named with its section ("objects.cell_size"); then each section's rules that
  // tie fields together, under the section's name.
  config::validateFields(config);
  const auto within = [](const char* section, const std::function<void()>& check) {
    try {
      check();
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument(std::string(section) + ": " + error.what());
    }
  };
  within("objects", [&] { validate(config.objects); });
  within("occupancy", [&] { validate(config.occupancy); });
  within("background", [&] { validate(config.background); });
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
