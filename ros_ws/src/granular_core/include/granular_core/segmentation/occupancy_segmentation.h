#pragma once

#include <cstddef>
#include <vector>

#include "granular_core/config/fields.h"
#include "granular_core/geometry/oriented_box.h"
#include "granular_core/point_types.h"

namespace granular {

/// Object detection of Himmelsbach et al., section II: a fresh 2.5-D occupancy grid around the
/// sensor per cloud, connected components of its occupied cells, one box per component. The
/// defaults are the paper's values (100 m x 100 m grid of 0.15 m cells, threshold 0.15 m).
struct SegmentationConfig {
  double cell_size = 0.15;  ///< m, edge of a grid cell
  /// m; the grid covers -extent/2 <= x, y < extent/2 in the cloud's frame (the sensor at the
  /// centre). Points outside are ignored. When extent is not a multiple of cell_size the last
  /// row and column of cells are cut at extent/2.
  double extent = 100.0;
  /// m; a cell is occupied when max z - min z of its points exceeds this.
  double height_threshold = 0.15;
  /// Occupied cells up to this many cells apart (in rows and columns) belong to one component;
  /// 1, the paper's, joins touching cells only (8-connectivity). A LiDAR whose returns lie
  /// farther apart than a cell along a surface (the simulated one's 1 deg azimuth step leaves
  /// 0.35 m at 20 m) splits an object into stripes unless gaps are bridged.
  int link_cells = 1;
  /// Components with fewer occupied cells are dropped (noise).
  std::size_t min_cells = 2;
  /// Boxes holding fewer points (Segment::indices) are dropped.
  std::size_t min_points = 5;
  /// m; boxes longer than this along either ground axis (walls, kerbs, hedges) are dropped.
  /// Not in the paper; infinity keeps every box.
  double max_length = 20.0;

  template <class Self, class Visit>
  static void fields(Self& self, Visit& visit) {
    visit("cell_size", self.cell_size, config::positive("m"));
    visit("extent", self.extent, config::positive("m"));
    visit("height_threshold", self.height_threshold, config::nonNegative("m"));
    visit("link_cells", self.link_cells, config::interval(1, 100, "cells"));
    visit("min_cells", self.min_cells, config::atLeast(1, "cells"));
    visit("min_points", self.min_points, config::nonNegative("points"));
    config::Spec longest = config::positive("m");
    longest.finite = false;
    visit("max_length", self.max_length, longest);
  }
};

/// Throws std::invalid_argument naming the field for a non-positive or non-finite cell_size or
/// extent, a grid of more than 10,000 cells a side, link_cells below 1, a negative or
/// non-finite height_threshold,
/// min_cells of 0 or a max_length that is not positive.
void validate(const SegmentationConfig& config);

/// One object hypothesis.
struct Segment {
  /// z-up box. Yaw from the principal axes of the component's cell centres (size x, the length,
  /// along the major axis; yaw in (-pi/2, pi/2]); length and width span the extremes of those
  /// centres plus the margin that makes the footprint enclose the whole cells; centre x, y in
  /// the middle of those extremes. Bottom at the lowest of `indices`, top at the highest:
  /// ground returns inside the footprint put the bottom on the ground. Height at least
  /// cell_size.
  OrientedBox box;
  /// Ascending indices into the cloud of every point whose x, y lie in the box's footprint
  /// (not only the component's cells), hence every point of the box. Boxes may overlap, and
  /// then share points.
  std::vector<std::size_t> indices;
  /// Occupied cells of the component.
  std::size_t cells = 0;
};

/// Segments `cloud` (sensor frame, z up) as described at SegmentationConfig. Non-finite points
/// and points outside the grid are ignored. The segments are in the order of their first cell
/// in a row-major scan of the grid (rows along y, from -extent/2). Validates `config` first.
std::vector<Segment> segmentCloud(const Cloud& cloud, const SegmentationConfig& config = {});

/// Counts of a comparison of segments against ground-truth boxes.
struct SegmentationMatch {
  std::size_t truth = 0;               ///< truth boxes
  std::size_t matched_truth = 0;       ///< truth boxes matched to a segment
  std::size_t segments = 0;            ///< segment boxes
  std::size_t unmatched_segments = 0;  ///< segment boxes matched to no truth box
};

/// Matches greedily, nearest pair first, by the x-y distance of the box centres; a pair farther
/// apart than max_distance (m) is never matched and each box is used at most once. Equal
/// distances are taken in order of truth index, then segment index. Throws
/// std::invalid_argument when max_distance is negative or not finite.
SegmentationMatch matchSegments(const std::vector<OrientedBox>& segments,
                                const std::vector<OrientedBox>& truth,
                                double max_distance = 1.0);

}  // namespace granular
